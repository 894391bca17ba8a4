"""Every command that reads a table reads the JSON another command writes (``-f json``), with the same
result as the CSV pipe: the JSON document carries the same metadata, and ``null`` is a missing cell."""

import pytest

from tests.cli.helpers import run

PIPES = [
    # (producer, consumer with '-' for the piped file, extra files: name -> producer)
    (
        ("simulate", "--mode", "2", "--tau-chips", "5", "--duration", "10", "-q"),
        ("detect", "-", "--horizons", "10"),
        {},
    ),
    (
        ("simulate", "--example", "2d", "--mode", "3", "--tau-chips", "2", "--duration", "4", "-q"),
        ("detect", "-", "--horizons", "4"),
        {},
    ),
    (("encode", "gps", "--prn", "1-3"), ("encode", "correlations", "-"), {}),
    (
        ("maneuver", "--view", "measurements", "--runs", "1", "--sigma", "100", "--scans", "60"),
        ("maneuver", "--input", "-", "--method", "all"),
        {},
    ),
    (
        ("slrt", "--view", "detections", "--runs", "1", "--scans", "10"),
        ("slrt", "--input", "-", "--sensor-table", "SENSORS", "--view", "decisions"),
        {"SENSORS": ("slrt", "--view", "sensors", "--runs", "1", "--scans", "10")},
    ),
]


@pytest.mark.parametrize(
    ("producer", "consumer", "files"), PIPES, ids=lambda v: " ".join(v)[:40] if isinstance(v, tuple) else ""
)
def test_json_output_pipes_like_csv(capsys, monkeypatch, tmp_path, producer, consumer, files):
    import io
    import sys

    names = {}
    for key, args in files.items():
        rc, out, err = run(capsys, *args, "-o", str(tmp_path / f"{key}.csv"))
        assert rc == 0, err
        names[key] = str(tmp_path / f"{key}.csv")
    consumer = tuple(names.get(a, a) for a in consumer)
    results = {}
    for fmt in ("csv", "json"):
        rc, text, err = run(capsys, *producer, "-f", fmt)
        assert rc == 0, err
        if fmt == "json":
            assert text.lstrip().startswith("{")
        monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(text.encode())))
        rc, out, err = run(capsys, *consumer)
        assert rc == 0, err
        results[fmt] = [ln for ln in out.splitlines() if not ln.startswith("#")]
    assert results["json"] == results["csv"] and len(results["csv"]) > 1
