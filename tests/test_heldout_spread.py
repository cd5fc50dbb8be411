"""The spread of the held-out figures (tvmedit.engine.lab.accuracy, ``bootstrap``): the suite's takes
drawn again within each group, the settings chosen anew on each draw."""

from types import SimpleNamespace

import numpy as np

from tvmedit.engine.lab.evaluate import Score


def result(found, true=2, false=0):
    # One take's score: ``found`` of its ``true`` changes found, ``false`` false boundaries,
    # one texton length right.
    segments = [{"start": 10 * k} for k in range(true + 1)]
    matches = [(10 * k, 10 * k) for k in range(1, found + 1)]
    return Score(found / max(found + false, 1), found / true, 1.0, matches, 10, segments, detected=found + false,
                 texton_rows=[(0, 0, 5.0, 5.0, True)])


def suite(found_a, found_b):
    # Two groups of three takes; one setting each per group's list of changes found.
    takes = [SimpleNamespace(group=g, name=f"{g}{k}") for g in "ab" for k in range(3)]
    return takes, [({"setting": 0}, [result(f) for f in found_a + found_b])]


def test_a_suite_without_errors_has_no_spread(devsuite):
    from tvmedit.engine.lab import accuracy
    takes, by_setting = suite([2, 2, 2], [2, 2, 2])
    draws = accuracy.bootstrap(takes, by_setting, [t.group for t in takes], n=50)
    assert draws.shape == (50, 3) and np.all(draws == 1.0)


def test_the_spread_follows_the_takes_and_holds_the_figure(devsuite, capsys):
    from tvmedit.engine.lab import accuracy
    # One take of group b finds none of its two changes: recall 4/6 there, 10/12 pooled.
    takes, by_setting = suite([2, 2, 2], [2, 2, 0])
    labels = [t.group for t in takes]
    draws = accuracy.bootstrap(takes, by_setting, labels, n=400)
    assert capsys.readouterr().out == ""                 # the draws' cross-validations print nothing
    recall = draws[:, 1]
    assert recall.min() < 10 / 12 < recall.max()
    assert recall.max() == 1.0                           # draws without the bad take
    assert abs(recall.mean() - 10 / 12) < 0.03
    assert np.all(draws[:, 0] == 1.0)                    # nothing false in any draw
    again = accuracy.bootstrap(takes, by_setting, labels, n=400)
    assert np.array_equal(draws, again)                  # the same draws each run
    accuracy.print_spread((1.0, 10 / 12, 1.0), draws)
    out = capsys.readouterr().out
    assert "recall         0.833, 90 % of draws" in out
    share = np.mean(recall >= 0.95)
    assert f"at or over 0.95 in {share:.0%}" in out and 0 < share < 1
    low, high = np.percentile(recall, [5, 95])
    assert f"recall         0.833, 90 % of draws {low:.3f}-{high:.3f}," in out


def test_each_group_is_drawn_from_its_own_takes(devsuite):
    from tvmedit.engine.lab import accuracy
    # Group a finds every change and group b none: drawn within each group, as many takes as
    # each has, every draw holds three of each, so recall is one half in every draw.
    takes, by_setting = suite([2, 2, 2], [0, 0, 0])
    draws = accuracy.bootstrap(takes, by_setting, [t.group for t in takes], n=200)
    assert np.all(draws[:, 1] == 0.5)


def test_the_settings_are_chosen_anew_on_each_draw(devsuite):
    from tvmedit.engine.lab import accuracy
    takes = [SimpleNamespace(group=g, name=f"{g}{k}") for g in "abc" for k in range(2)]
    labels = [t.group for t in takes]
    # In groups a and b, setting 1 misses take b1's changes and setting 2 take a0's; neither
    # places a false boundary there. In group c, setting 1 places a false boundary and
    # setting 2 none. Held out, group c is scored with whichever did better on a and b: setting
    # 1 in a draw without b1 and with a0, setting 2 in one with b1 and without a0.
    one = [result(2), result(2), result(2), result(0), result(2, false=1), result(2, false=1)]
    two = [result(0), result(2), result(2), result(2), result(2), result(2)]
    by_setting = [({"s": 1}, one), ({"s": 2}, two)]
    precision = accuracy.bootstrap(takes, by_setting, labels, n=200)[:, 0]
    # Only group c can place a false boundary: had one setting served every draw, precision
    # would be under 1 in every draw (setting 1) or 1 in every draw (setting 2).
    assert (precision == 1.0).any() and (precision < 1.0).any()
