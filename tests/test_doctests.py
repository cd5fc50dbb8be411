"""Every docstring example of the package runs and prints what it shows."""

import doctest
import importlib
import pkgutil

import pytest

import tvmedit


def _modules():
    names = ["tvmedit"]
    for info in pkgutil.walk_packages(tvmedit.__path__, "tvmedit."):
        names.append(info.name)
    for package in ("tvmedit.engine", "tvmedit.player"):
        module = importlib.import_module(package)
        names.append(package)
        names += [info.name for info in pkgutil.walk_packages(module.__path__, package + ".")]
    return sorted(name for name in set(names) if not name.endswith("__main__"))


@pytest.mark.parametrize("name", _modules())
def test_docstring_examples_run_as_shown(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples in {name} failed"
