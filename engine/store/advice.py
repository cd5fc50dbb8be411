"""Advice that works: parse settings tried when a build gives fewer than two motions.

A take that parses into one motion cannot be edited. Rather than name options that may or may
not help, the builder re-parses the features it already has with a few settings, in order
(:data:`MORE_MOTIONS`: shorter clusters, cheaper changes of the partition, both, and a lower
novelty threshold with them) and names the first that gives two motions or more, with how
many (:func:`tvmedit.engine.graph.database.advice` words it). A re-parse is well under a
second a take, and it runs only when the build would otherwise end without an edit.
"""

import dataclasses
import warnings

from ..graph.database import build_database
from ..parse import structure as structure_module

__all__ = ["MORE_MOTIONS", "more_motions"]


#: Parse settings tried, in order, when a build gives fewer than two motions (each a re-parse
#: of the features, well under a second a take): shorter clusters, cheaper changes, both.
MORE_MOTIONS = ({"min_cluster": 1.0}, {"partition": 5.0}, {"min_cluster": 1.0, "partition": 5.0},
                {"min_cluster": 1.0, "partition": 5.0, "novelty_threshold": 0.5})


def more_motions(sequences, padded, vectors, params):
    """The first of :data:`MORE_MOTIONS` whose parse gives two motions or more, with their
    count; None where none does (what the advice then says is untried)."""
    for setting in MORE_MOTIONS:
        tried = dataclasses.replace(params, **setting)
        if tried == params:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            parses = {seq.name: structure_module.parse(vectors[seq.name], seq.fps, tried, theta=f.theta_columns,
                                                       centred=f.centred) for seq, f in zip(sequences, padded)}
        count = len(build_database(parses))
        if count >= 2:
            return setting, count
    return None
