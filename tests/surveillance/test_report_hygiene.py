"""Record hygiene (surveillance.report_hygiene): sorting, duplicates, stale repeats, gaps, strict refusals."""

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.surveillance.report_hygiene import HygieneError, HygienePolicy, clean_reports


def test_a_real_feed_is_sorted_deduplicated_and_cut_at_gaps():
    t = np.array([2.0, 0.0, 1.0, 1.0, 1.0, 3.0, 4.0, 60.0, 61.0, 62.0])
    pos = np.array([[2, 0], [0, 0], [1, 0], [1, 0], [1, 5], [2, 0], [4, 0], [60, 0], [np.nan, np.nan], [62, 0]],
                   float)  # fmt: skip
    c = clean_reports(t, pos)
    # time order: rows 1 (t 0), 2 (t 1), 3 exact duplicate, 4 conflicting, 0 (t 2), 5 stale repeat of row 0;
    # the first five rows of the file moved in the sort
    assert c.rows.tolist() == [1, 2, 0, 6, 7, 8, 9]
    assert c.counts == {"reordered": 5, "exact_duplicates": 1, "conflicting_duplicates": 1,
                        "empty_duplicates": 0, "stale_repeats": 1, "gaps": 1}  # fmt: skip
    assert c.segment.tolist() == [0, 0, 0, 0, 1, 1, 1] and c.max_gap == 30.0


def test_stale_repeats_can_be_kept_and_the_gap_limit_given():
    t = np.arange(10.0)
    pos = np.repeat(np.arange(5.0), 2)[:, None] * np.ones((1, 2))
    keep = clean_reports(t, pos, HygienePolicy(stale="keep", max_gap=0.5))
    assert keep.rows.size == 10 and keep.counts["stale_repeats"] == 5 and keep.segment[-1] == 9
    drop = clean_reports(t, pos)
    assert drop.rows.tolist() == [0, 2, 4, 6, 8]


@pytest.mark.parametrize(
    ("t", "pos", "row", "what"),
    [
        ([0.0, 2.0, 1.0], [[0, 0], [2, 0], [1, 0]], 2, "earlier than the row before"),
        ([0.0, 1.0, 1.0], [[0, 0], [1, 0], [1, 0]], 2, "repeats the time"),
        ([0.0, 1.0, 1.0], [[0, 0], [1, 0], [1, 3]], 2, "another position"),
    ],
)
def test_strict_refuses_naming_the_row(t, pos, row, what):
    with pytest.raises(HygieneError) as exc:
        clean_reports(np.array(t), np.array(pos, float), HygienePolicy(strict=True))
    assert exc.value.row == row and what in exc.value.message


def test_a_bad_policy_names_its_field():
    for kw, field in (({"stale": "maybe"}, "stale"), ({"max_gap": -1.0}, "max_gap")):
        with pytest.raises(ConfigError) as exc:
            HygienePolicy(**kw)
        assert exc.value.field == field
