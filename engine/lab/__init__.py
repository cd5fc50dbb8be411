"""The lab: data with known answers, and the scorer that reads them.

- :mod:`.synth`: the synthetic capture actor (``tvmedit synth``, the built-in data set), which
  writes takes; :mod:`.exercises` poses it over a cycle and lays out its timeline, and
  :mod:`.body` reconstructs its surface frame by frame;
- :mod:`.evaluate`: a parse scored against labelled truth (``truth.json``);
- :mod:`.devsuite` and :mod:`.fresh`: the parser's development suite and its out-of-sample
  batches, made from the real motion in ``../shared``; :mod:`.suitedata` holds what a take of
  the suite is made of (feature rows, cached, and truth);
- :mod:`.accuracy`: the suite scored per group, pooled and held out
  (``python -m tvmedit.engine.lab.accuracy``).
"""
