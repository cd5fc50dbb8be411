"""The parser's parameters (tvmedit.engine.parse.params.StructureParams): each checked at the
door with a sentence naming it, the novelty threshold following its rows, and the parameters
a library recorded read back as that parse was made."""

import dataclasses

import pytest

from tvmedit.engine.errors import ParameterError
from tvmedit.engine.parse.params import BEFORE, RAW_THRESHOLD, WHITENED_THRESHOLD, StructureParams


@pytest.mark.parametrize("values, words", [
    (dict(beta=-1), "beta=-1 is out of range"),
    (dict(min_texton=0), "min_texton=0 is out of range"),
    (dict(novelty_components=1.5), "novelty_components=1.5 must be a whole number"),
    (dict(window_taps=(1.0, 1.0)), "window_taps has 2 taps"),
    (dict(window_taps=(0, 0, 0)), "not all 0"),
    (dict(window_fps=0.1), "window_fps=0.1 makes the atom window 40 s long"),
    (dict(max_period=0.4), "max_period=0.4 must be above min_texton=0.4"),
    (dict(method="magic"), "use 'energy' or 'paper'"),
    (dict(rhythm_ratio=0.5), "use 0 to leave weak peaks out"),
])
def test_a_parameter_out_of_range_is_refused_by_name(values, words):
    with pytest.raises(ParameterError, match=words):
        StructureParams(**values)


def test_parameter_errors_are_value_errors():
    with pytest.raises(ValueError):
        StructureParams(method="magic")


def test_the_novelty_threshold_follows_whether_rows_are_whitened():
    assert StructureParams().novelty_threshold == WHITENED_THRESHOLD == 0.9
    assert StructureParams(novelty_components=0).novelty_threshold == RAW_THRESHOLD == 0.05
    assert StructureParams.recorded({}).novelty_threshold == 0.05   # a parse made before whitening
    with pytest.warns(UserWarning, match="units of the take's own spread"):
        StructureParams(novelty_threshold=0.05)                     # an older script's threshold
    with pytest.warns(UserWarning, match="few or no boundaries"):
        StructureParams(novelty_components=0, novelty_threshold=0.9)


def test_taps_given_as_a_list_are_kept_as_a_tuple_of_floats():
    p = StructureParams(window_taps=[1, 2, 1])
    assert p.window_taps == (1.0, 2.0, 1.0) and all(isinstance(x, float) for x in p.window_taps)


def test_recorded_parameters_leave_out_rules_added_since():
    old = StructureParams.recorded({"min_cluster": 3.0, "unknown": 1})
    assert old.min_cluster == 3.0
    assert all(getattr(old, name) == value for name, value in BEFORE.items())
    assert StructureParams.recorded(dataclasses.asdict(StructureParams())) == StructureParams()


def test_every_rule_added_since_the_first_libraries_is_a_parameter():
    names = {f.name for f in dataclasses.fields(StructureParams)}
    assert set(BEFORE) <= names
