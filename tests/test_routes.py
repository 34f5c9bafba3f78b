"""agents.analysis.routes: test episodes grouped by where their paths first cross a line."""

import json

import pytest

from agents.analysis.routes import NEVER, bin_label, by_route, crossing, main, parse_line


def _eval(path, episodes):
    path.mkdir()
    (path / "eval.json").write_text(json.dumps({"task": "DynNav-VisualStaticTarget-v1", "episodes": episodes}))
    return path


def test_the_first_point_on_or_past_the_line_gives_the_route():
    path = [[0.0, 0.0], [1.0, 0.5], [2.0, 1.0], [0.5, 2.0]]
    assert crossing(path, 1, 1.0) == 2.0  # first y >= 1 at x = 2, not the later x = 0.5
    assert crossing(path, 0, 1.0) == 0.5  # first x >= 1 at y = 0.5
    assert crossing(path, 1, 3.0) is None
    assert [bin_label(x, [0.35, 3.0]) for x in (0.0, 0.35, 2.9, 3.0, None)] == ["< 0.35", "0.35-3", "0.35-3",
                                                                                ">= 3", NEVER]


def test_episodes_of_several_runs_are_grouped_by_route(tmp_path, capsys):
    east = [[-0.5, -0.5], [3.5, 0.0], [3.5, 1.2]]
    across = [[-0.5, -0.5], [1.0, 1.0]]
    a = _eval(tmp_path / "a", [dict(outcome="success", steps=60, ret=-5.0, trajectory=east),
                               dict(outcome="collision", steps=20, ret=-40.0, trajectory=across)])
    b = _eval(tmp_path / "b", [dict(outcome="success", steps=40, ret=-3.0, trajectory=across),
                               dict(outcome="collision", steps=5, ret=-30.0, trajectory=[[-0.5, -0.5]])])
    groups = by_route([a, b], *parse_line("y=1"), [0.35, 3.0])
    assert {k: [e["outcome"] for e in v] for k, v in groups.items()} == {
        ">= 3": ["success"], "0.35-3": ["collision", "success"], NEVER: ["collision"]}
    main([str(a), str(b), "--line", "y=1", "--edges", "0.35", "3"])
    rows = capsys.readouterr().out.splitlines()
    assert "| 0.35-3 | 2 | 50% | 50% | 0% | 40.0 | -21.5 |" in rows
    assert "| >= 3 | 1 | 100% | 0% | 0% | 60.0 | -5.0 |" in rows


def test_bad_lines_and_edges_are_refused():
    with pytest.raises(ValueError, match="x=VALUE or y=VALUE"):
        parse_line("z=1")
    with pytest.raises(ValueError, match="not a number"):
        parse_line("y=one")
    with pytest.raises(SystemExit):
        main(["somewhere", "--line", "y=1", "--edges", "3", "1"])
