"""A build's settings (tvmedit.engine.store.settings): defaults filled in, each checked at the door."""

import pytest

from tvmedit import build
from tvmedit.engine.errors import ParameterError
from tvmedit.engine.features import BinSizes
from tvmedit.engine.graph.motiongraph import MU
from tvmedit.engine.parse.params import StructureParams
from tvmedit.engine.store.settings import Settings
from conftest import snippet_inputs as _inputs



@pytest.mark.parametrize("mu", [float("inf"), float("nan"), -1.0, 0.0, "abc"])
def test_mu_must_be_finite_and_positive(take_13_30, tmp_path, mu):
    with pytest.raises(ParameterError, match=r"mu=.* is out of range: it must be a finite number above 0 \(the default is 0.9\)\.$"):
        build(_inputs(take_13_30), tmp_path / "lib", workers=1, mu=mu)
    assert not list(tmp_path.iterdir())


def test_keep_frames_must_be_motions_or_all(take_13_30, tmp_path):
    with pytest.raises(ParameterError, match="keep_frames='some' is not one of 'motions', 'all'"):
        build(_inputs(take_13_30), tmp_path / "x.tvmlib", keep_frames="some")
    assert not (tmp_path / "x.tvmlib").exists()


def test_settings_left_out_take_the_defaults():
    settings = Settings.of(None, None, None, 0)
    assert settings == Settings(BinSizes(), StructureParams(), MU, False, "auto", None, "motions")


def test_structure_parameters_given_as_a_dict_override_the_defaults():
    settings = Settings.of(BinSizes(r=0.04), {"window_fps": 5.0}, "2", True, blend_frames=3.0)
    assert settings.params == StructureParams(window_fps=5.0)
    assert (settings.bins, settings.mu, settings.skip_bad_frames, settings.blend_frames) == (
        BinSizes(r=0.04), 2.0, True, 3)


def test_an_unknown_structure_parameter_is_refused_naming_the_known():
    with pytest.raises(ParameterError, match=r"structure has no parameter 'speed'; it has .*window_fps"):
        Settings.of(None, {"speed": 1, "window_fps": 5.0}, None, False)


def test_an_unknown_connect_mode_is_refused_naming_the_modes():
    with pytest.raises(ParameterError, match=r"connect='always' is not one of 'auto', "):
        Settings.of(None, None, None, False, connect="always")
