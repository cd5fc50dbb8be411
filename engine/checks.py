"""Checks at the door: every parameter a caller gives is tested here, with one sentence.

The engine names a parameter as Python does, ``name=value``; the command line turns that
into its own option (``--name value``). Every number must be finite and in its range, and
every size that sets how much work or memory a call takes has a limit that is named, so a
typo never allocates gigabytes or runs for ever.

>>> number("mu", 0.9, above=0)
0.9
>>> number("analysis_fps", 0, above=0, at_most=MAX_FPS)
Traceback (most recent call last):
...
tvmedit.engine.errors.ParameterError: analysis_fps=0 is out of range: it must be a finite number above 0 and at most 1000.
"""

import math
import numbers

from .errors import ParameterError

__all__ = ["MAX_FPS", "MAX_LOOPS", "number", "whole", "listed", "json_value"]

#: Highest frame rate accepted anywhere (capture, analysis, output); work grows with it.
MAX_FPS = 1000
#: Most cycles of the last key motion an edit may play (its schedule is held in memory).
MAX_LOOPS = 10000


def _shown(value):
    return f"{value:g}" if isinstance(value, float) else str(value)


def _rule(above, at_least, below, at_most):
    parts = []
    if above is not None:
        parts.append(f"above {_shown(above)}")
    if at_least is not None:
        parts.append(f"at least {_shown(at_least)}")
    if below is not None:
        parts.append(f"below {_shown(below)}")
    if at_most is not None:
        parts.append(f"at most {_shown(at_most)}")
    return " and ".join(parts)


def number(name, value, *, above=None, at_least=None, below=None, at_most=None, hint=""):
    """``value`` as a float when it is a finite number in range, else a :class:`ParameterError`.

    ``hint`` is appended to the sentence (e.g. why the limit is there).
    """
    try:
        ok = isinstance(value, (numbers.Real, str)) and not isinstance(value, bool)
        result = float(value) if ok else math.nan
    except ValueError:
        result = math.nan
    if not (math.isfinite(result)
            and (above is None or result > above) and (at_least is None or result >= at_least)
            and (below is None or result < below) and (at_most is None or result <= at_most)):
        rule = _rule(above, at_least, below, at_most)
        shown = value if isinstance(value, (numbers.Real, str)) and not isinstance(value, bool) else repr(value)
        raise ParameterError(f"{name}={shown} is out of range: it must be a finite number"
                             f"{' ' + rule if rule else ''}{hint}.")
    return result


def whole(name, value, *, at_least=None, at_most=None, hint=""):
    """``value`` as an int when it is a whole number in range, else a :class:`ParameterError`.

    >>> whole("loops", 3, at_least=1)
    3
    """
    result = number(name, value, at_least=at_least, at_most=at_most, hint=hint)
    if result != int(result):
        raise ParameterError(f"{name}={value} must be a whole number.")
    return int(result)


def listed(name, value, what="motion ids or names"):
    """``value`` as a list, or one sentence where it is not a list of items: a string (or bytes,
    or a mapping) would otherwise be read one character or key at a time, so that
    ``edit('01')`` went from motion 0 to motion 1. None stays None.

    >>> listed("keys", ("walk", 3))
    ['walk', 3]
    >>> listed("keys", "01")
    Traceback (most recent call last):
    ...
    tvmedit.engine.errors.ParameterError: keys='01' should be a list of motion ids or names, not a string: write ['01'] for one.
    """
    if value is None:
        return None
    if isinstance(value, (str, bytes, dict)):
        kind = "a mapping" if isinstance(value, dict) else "a string"
        raise ParameterError(f"{name}={value!r} should be a list of {what}, not {kind}: write [{value!r}] for one.")
    try:
        return list(value)
    except TypeError:
        raise ParameterError(f"{name}={value!r} should be a list of {what}.") from None


def json_value(text):
    """``json.loads(text)``, where JSON nested too deeply to read (a RecursionError in the
    decoder) is a ValueError like any other bad JSON, so every reader's one-sentence error
    covers it.

    >>> json_value('{"fps": 30}')
    {'fps': 30}
    >>> json_value("[" * 100000)
    Traceback (most recent call last):
    ...
    ValueError: nested too deeply to read
    """
    import json

    try:
        return json.loads(text)
    except RecursionError:
        raise ValueError("nested too deeply to read") from None
