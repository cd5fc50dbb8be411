"""The lab: data with known answers, and the scorer that reads them.

- :mod:`.synth`: the synthetic capture actor (``tvmedit synth``, the built-in data set);
- :mod:`.evaluate`: a parse scored against labelled truth;
- :mod:`.devsuite` and :mod:`.fresh`: the parser's development suite and its out-of-sample
  batches, made from the real motion in ``../shared``.
"""
