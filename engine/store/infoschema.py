"""The JSON schema of ``tvmedit info --json``: what :meth:`tvmedit.engine.store.library.Library.info` gives.

Kept beside the library's reader, in a module of its own, so that a program reading the
summary can check it (``jsonschema.validate(info, INFO_SCHEMA)``) without the reader's code.
"""

__all__ = ["INFO_SCHEMA"]

_INT = {"type": "integer", "minimum": 0}
_NUM = {"type": "number"}
_RANGE = {"start": _INT, "end": _INT}
#: How sure the parse is of a cluster's starting boundary or of a texton, 0-1 (tvmedit.engine.parse.confidence);
#: null for a library built before confidences were recorded.
_CONFIDENCE = {"type": ["number", "null"], "minimum": 0, "maximum": 1}

#: JSON schema of ``tvmedit info --json`` (:meth:`Library.info`). Frame ranges are inclusive
#: and 0-based within their sequence, exit and entry frames likewise; edges are those of the
#: graph (pruned, and ``added`` where put back to connect it), ``from`` and ``to`` are node ids.
INFO_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "title": "tvmedit library info",
    "type": "object",
    "required": ["format", "params", "sequences", "nodes", "edges"],
    "properties": {
        "format": {"type": "integer", "description": "on-disk format version"},
        "natural_step": {"type": "number", "description": "median Chamfer distance between "
                                                          "consecutive texton frames, metres"},
        "tvmedit": {"type": "string", "description": "version that built the library"},
        "params": {
            "type": "object",
            "description": "build parameters: bins (r in metres, theta and phi in radians), "
                           "structure (the parser's parameters), mu, skip_bad_frames, "
                           "connect (auto: edges added so every motion reaches every other; off)",
            "required": ["bins", "structure", "mu"],
            "properties": {
                "bins": {"type": "object", "required": ["r", "theta", "phi"],
                         "properties": {"r": _NUM, "theta": _NUM, "phi": _NUM}},
                "structure": {"type": "object"},
                "mu": _NUM,
                "skip_bad_frames": {"type": "boolean"},
                "connect": {"enum": ["auto", "off"]},
            },
        },
        "sequences": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["name", "frames", "fps", "clusters", "textons"],
                "properties": {
                    "name": {"type": "string"},
                    "frames": _INT,
                    "fps": {"type": "number", "exclusiveMinimum": 0},
                    "clusters": {"type": "array", "items": {
                        "type": "object", "required": ["start", "end"],
                        "properties": {**_RANGE, "confidence": _CONFIDENCE}}},
                    "textons": {"type": "array", "items": {
                        "type": "object", "required": ["start", "end", "cluster"],
                        "properties": {**_RANGE, "cluster": _INT, "distance": _NUM, "confidence": _CONFIDENCE}}},
                    "corrections": {"type": "object", "description": "corrections by hand applied "
                                    "on top of the automatic parse, as in corrections.json "
                                    "(tvmedit.engine.store.corrections); absent when none"},
                },
            },
        },
        "nodes": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["id", "name", "sequence", "start", "end", "texton_distance", "intensity"],
                "properties": {"id": _INT, "name": {"type": "string"}, "sequence": {"type": "string"},
                               **_RANGE, "cluster": _INT, "texton_distance": _NUM,
                               "intensity": {"type": ["number", "null"]},
                               "kind": {"enum": ["cycle", "once"],
                                        "description": "cycle: a texton played cyclically; once: a "
                                                       "one-shot motion played through once"},
                               "closing_frames": {**_INT, "description": "texton frames warped onto "
                                                  "the neighbouring repetition where its loop wraps, "
                                                  "so the wrap does not pop (tvmedit.engine.inbetween.loops); 0: none"}},
            },
        },
        "edges": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["from", "to", "weight", "exit_frame", "entry_frame"],
                "properties": {"from": _INT, "to": _INT, "weight": _NUM,
                               "exit_frame": _INT, "entry_frame": _INT,
                               "added": {"type": "boolean",
                                         "description": "put back from the complete graph so that every "
                                                        "motion reaches every other (tvmedit.engine.graph.connect)"},
                               "blend_frames": {**_INT, "description": "in-between frames stored "
                                                "for this transition (tvmedit.engine.inbetween.blend)"},
                               "jump": {**_NUM, "description": "Chamfer distance of the cut, metres"}},
            },
        },
        "connect": {
            "type": "object",
            "description": "how the pruned graph was made strongly connected",
            "required": ["mode", "added", "largest_weight", "reason"],
            "properties": {"mode": {"enum": ["auto", "off"]}, "added": _INT,
                           "largest_weight": {"type": ["number", "null"]},
                           "fewest": {"type": "boolean"}, "components_before": _INT,
                           "reason": {"type": "string"}},
        },
    },
}
