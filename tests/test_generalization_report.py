"""RESULTS.md's generalization section (agents.study.generalization via agents.study.report): the
procedural navigators on their test and ood worlds beside the planner and the floor, the figure
of success against world size and crowding, and 5.3's navigator tested with more and faster boxes."""

import json
from pathlib import Path

import pytest

from agents.study.report import write_report
from agents.study.run_record import social_columns
from agents.study.table import EPISODE_COLUMNS, RUN_COLUMNS, add_rows, read_table

FIXED = "DynNav-MovingObstacles-v1"
PROCEDURAL = "DynNav-Procedural-v1"
MORE_BOXES = "obstacle_count=4,obstacle_speed_scale=1.5"
TEST, OOD = "difficulty=easy,split=test", "difficulty=easy,split=ood"


def run_row(experiment: str, seed: int, success: float, tested_on: str = "", task: str = FIXED,
            collision: float = 0.0, spl: float = 0.5) -> dict:
    """A run row as agents.study.table stores it: 100 test episodes, 400 training episodes."""
    row = dict(experiment=experiment, config_hash="0123456789ab", seed=seed, tested_on=tested_on, task=task, commit="",
               run=f"{task}__{experiment}__{seed}__20260101-000000", test_episodes=100, success_rate=success,
               collision_rate=collision, timeout_rate=round(1 - success - collision, 6), avg_steps_success=40.0,
               spl=spl, avg_return=-10.0, converge_episode=300, wall_clock_s=60.0, train_s=55.0, eval_s=5.0,
               episodes_planned=400, episodes_done=400, curve_block=50, curve_return=" ".join(["-5"] * 8),
               curve_loss=" ".join(["nan"] + ["0.5"] * 7), curve_success=" ".join(["0.5"] * 8),
               **social_columns(None))  # no pedestrians
    assert set(row) == set(RUN_COLUMNS)
    return row


def episode_rows(run: dict, worlds: list[tuple[float, int]]) -> list[dict]:
    """The run's test episodes in worlds of (arena side, moving obstacles); every third one succeeds."""
    rows = [dict({k: run[k] for k in ("experiment", "config_hash", "seed", "tested_on")}, episode=i,
                 episode_seed=1_000_000 + i, outcome="success" if i % 3 == 0 else "collision", steps=40,
                 episode_return=-1.0, spl=0.5 if i % 3 == 0 else 0.0, world_seed=100 + i, arena_side=side,
                 moving_obstacles=boxes) for i, (side, boxes) in enumerate(worlds)]
    assert all(set(r) == set(EPISODE_COLUMNS) for r in rows)
    return rows


def study_table(folder: Path) -> Path:
    """5.3 (seeds 1-2) at home and with more and faster boxes, and procedural-easy (seeds 1-2) on
    its test worlds (6-8 m, 0-3 boxes) and ood worlds (14-20 m, 6-12 boxes), 40 episodes each."""
    runs = [run_row("5.3", 1, 0.90, collision=0.08), run_row("5.3", 2, 0.80, collision=0.15),
            run_row("5.3", 1, 0.35, MORE_BOXES, collision=0.60), run_row("5.3", 2, 0.45, MORE_BOXES, collision=0.50),
            run_row("procedural-easy", 1, 0.61, TEST, PROCEDURAL, collision=0.30, spl=0.52),
            run_row("procedural-easy", 2, 0.73, TEST, PROCEDURAL, collision=0.20, spl=0.60),
            run_row("procedural-easy", 1, 0.20, OOD, PROCEDURAL, collision=0.70, spl=0.15),
            run_row("procedural-easy", 2, 0.34, OOD, PROCEDURAL, collision=0.60, spl=0.21)]
    episodes = []
    for run in runs:
        if run["tested_on"] == TEST:
            episodes += episode_rows(run, [(6.0 + 0.1 * (i % 20), i % 4) for i in range(40)])
        elif run["tested_on"] == OOD:
            episodes += episode_rows(run, [(14.0 + 0.3 * (i % 20), 6 + i % 7) for i in range(40)])
        elif run["tested_on"] == MORE_BOXES:
            episodes += episode_rows(run, [(6.5, 4)] * 40)
    add_rows(folder, runs, episodes)
    return folder


def write_ceilings(folder: Path) -> None:
    """The planner's ceilings where the report looks by default (docs/results/ next to it)."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "ceilings.json").write_text(json.dumps({
        FIXED: dict(success=0.98, collision=0.02, timeout=0.0, episodes=200, first_seed=0),
        f"{FIXED} [{MORE_BOXES}]": dict(success=0.71, collision=0.29, timeout=0.0, episodes=200, first_seed=0)}))
    cells = {f"{controller}/easy/{split}": dict(task=PROCEDURAL, difficulty="easy", split=split, success=success,
                                                collision=1 - success, timeout=0.0, episodes=200, spl=spl)
             for controller, split, success, spl in [("state_planner", "test", 0.95, 0.81),
                                                     ("state_planner", "ood", 0.70, 0.55),
                                                     ("go_to_target", "test", 0.40, 0.38),
                                                     ("go_to_target", "ood", 0.10, 0.09)]}
    (folder / "procedural_ceilings.json").write_text(json.dumps(cells))


def section(text: str, title: str) -> str:
    return text.split(f"## {title}\n")[1].split("\n## ")[0]


def line_starting(text: str, start: str) -> str:
    (line,) = [line for line in text.splitlines() if line.startswith(start)]
    return line


def test_the_generalization_section_sets_each_test_beside_the_planner(tmp_path):
    table = study_table(tmp_path / "results")
    write_ceilings(tmp_path / "docs" / "results")
    text = write_report(table, out=tmp_path / "RESULTS.md").read_text()
    general = section(text, "Generalization")
    # seeds 61% and 73%: mean 67%, sd 8.5 points; collision (30 + 20) / 2, timeout (9 + 7) / 2, SPL (0.52 + 0.60) / 2
    assert line_starting(general, "| `procedural-easy` | easy/test |") == (
        "| `procedural-easy` | easy/test | 2 | 67% (8%) | 25% | 8% | 0.56 | 95% (0.81) | 40% |")
    # seeds 20% and 34%: mean 27%, sd 9.9 points; collision 65%, timeout (10 + 6) / 2
    assert line_starting(general, "| `procedural-easy` | easy/ood |") == (
        "| `procedural-easy` | easy/ood | 2 | 27% (10%) | 65% | 8% | 0.18 | 70% (0.55) | 10% |")
    assert general.index("easy/test") < general.index("easy/ood")
    # 5.3 at home (90%, 80%) and with more boxes (35%, 45%; collision 60%, 50%), each beside the planner
    assert line_starting(general, "| `5.3` |") == (
        f"| `5.3` | `{MORE_BOXES}` | 2 | 85% | 40% | 55% | 5% | 98% | 71% |")
    figure = tmp_path / "docs" / "results" / "generalization.png"
    assert "](docs/results/generalization.png)" in general
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and figure.stat().st_size > 5000

    every = section(text, "Every experiment")
    assert "procedural-easy" not in every and MORE_BOXES not in every
    # 5.3's row holds its own tests only: 2 seeds, (90% + 80%) / 2
    assert "| `5.3` | MovingObstacles | 2 | 85% (" in line_starting(every, "| `5.3` |")
    assert line_starting(every, "| `5.3` |").endswith("| 90% 80% |")


def test_without_the_planners_numbers_the_cells_say_so(tmp_path):
    table = study_table(tmp_path / "results")
    general = section(write_report(table, out=tmp_path / "RESULTS.md").read_text(), "Generalization")
    assert line_starting(general, "| `procedural-easy` | easy/test |").endswith("| not measured | not measured |")
    assert line_starting(general, "| `5.3` |").endswith("| 85% | 40% | 55% | 5% | - | - |")


def test_a_table_without_tests_in_other_worlds_has_no_such_section(tmp_path):
    add_rows(tmp_path / "results", [run_row("5.3", 1, 0.9), run_row("5.3", 2, 0.8)], [])
    text = write_report(tmp_path / "results", out=tmp_path / "RESULTS.md").read_text()
    assert "## Generalization" not in text
    assert not (tmp_path / "docs" / "results" / "generalization.png").exists()


def test_a_missing_procedural_ceilings_file_is_refused_before_anything_is_written(tmp_path):
    table = study_table(tmp_path / "results")
    with pytest.raises(ValueError, match="procedural ceilings file .*nowhere.json.* does not exist"):
        write_report(table, out=tmp_path / "out" / "RESULTS.md", procedural_ceilings=tmp_path / "nowhere.json")
    assert not (tmp_path / "out").exists()
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"state_planner/easy/test": 0.9}))
    with pytest.raises(ValueError, match="is not what the baselines' --out writes"):
        write_report(table, out=tmp_path / "out" / "RESULTS.md", procedural_ceilings=bad)
    assert not (tmp_path / "out").exists()



def test_the_figure_shows_the_procedural_tests_only(tmp_path):
    full = study_table(tmp_path / "full")
    procedural = [lambda r: True, lambda r: r["experiment"] != "5.3" or not r["tested_on"]]  # with / without transfer
    pictures = []
    for i, keep in enumerate(procedural):
        table = tmp_path / str(i) / "results"
        runs, episodes = read_table(full), read_table(full, episodes=True)
        add_rows(table, [r for r in runs if keep(r)], [e for e in episodes if keep(e)])
        write_report(table, out=tmp_path / str(i) / "RESULTS.md")
        pictures.append((tmp_path / str(i) / "docs" / "results" / "generalization.png").read_bytes())
    assert pictures[0] == pictures[1]


def test_the_generalist_and_its_ablation_have_tables_of_their_own():
    from agents.study.generalist import ablation_table, generalist_table
    from agents.study.generalization import procedural_table

    hard_test, hard_ood = "difficulty=hard,split=test", "difficulty=hard,split=ood"
    rows = [run_row("procedural-hard", 1, 0.40, hard_test, PROCEDURAL), run_row("procedural-hard", 2, 0.30, hard_test,
                                                                                PROCEDURAL),
            run_row("generalist-dagger", 1, 0.70, hard_test, PROCEDURAL), run_row("generalist-dagger", 2, 0.80, hard_test,
                                                                                  PROCEDURAL),
            run_row("generalist-dagger", 1, 0.90, hard_ood, PROCEDURAL),
            run_row("generalist-dagger", 1, 0.25, "study_world=5.3-transfer", PROCEDURAL),
            run_row("ablation-conv-16", 1, 0.60, hard_test, PROCEDURAL),
            run_row("ablation-conv-16", 1, 0.80, "difficulty=medium,split=test", PROCEDURAL)]
    cells = {"state_planner/hard/test": dict(success=0.88, spl=0.8), "state_planner/hard/ood": dict(success=0.96, spl=0.9)}
    ceilings = {"DynNav-MovingObstacles-v1 [obstacle_count=4,obstacle_speed_scale=1.5]": 0.32}
    table = generalist_table(rows, cells, ceilings)
    def cells_of(line: str) -> list[str]:
        return [c.strip() for c in line.strip().strip("|").split("|")]

    head = cells_of(table[0])
    at = {name: head.index(name) for name in ("hard test", "hard ood", "5.3 transfer")}
    planner, dqn, dagger, goal = (cells_of(line) for line in (table[2], table[3], table[4], table[5]))
    assert (planner[at["hard test"]], planner[at["hard ood"]], planner[at["5.3 transfer"]]) == ("88%", "96%", "32%")
    assert dqn[at["hard test"]] == "35%" and dqn[1] == "2"  # the per-difficulty navigator, mean of two seeds
    assert (dagger[at["hard test"]], dagger[at["hard ood"]], dagger[at["5.3 transfer"]]) == ("75%", "90%", "25%")
    assert goal[at["hard test"]] == "≥ 79%" and goal[at["hard ood"]] == "≥ 72%"  # 90% and 75% of the planner's
    (ablation,) = ablation_table(rows)[2:]
    assert ablation.startswith("| `conv-16` | 1 | - | 80% | 60% | 70% | 55 |")
    assert [line for line in procedural_table(rows, cells) if "generalist" in line or "ablation" in line] == []


def test_the_generalists_learning_curves_are_drawn_once_it_has_a_run(tmp_path):
    """The per-difficulty runs alone draw no generalist figure; with a generalist run RESULTS.md
    shows its success and return curves beside theirs."""
    per_difficulty = [run_row(f"procedural-{d}", 1, 0.5, "", PROCEDURAL) for d in ("easy", "medium", "hard")]
    generalist = [dict(run_row("generalist-finetune", 1, 0.7, "", PROCEDURAL),
                       curve_success=" ".join(["0.6"] * 4 + ["0.8"] * 4))]
    for name, rows in (("without", per_difficulty), ("with", per_difficulty + generalist)):
        add_rows(tmp_path / name / "results", rows, [])
        text = write_report(tmp_path / name / "results", out=tmp_path / name / "RESULTS.md").read_text()
        drawn = (tmp_path / name / "docs" / "results" / "generalist.png").is_file()
        assert drawn == (name == "with") and ("(docs/results/generalist.png)" in text) == drawn


def test_the_generalist_page_shows_the_tables_of_the_run_table():
    """docs/generalist.md's tables are those ``python -m agents.study.generalist`` makes from results/."""
    import re

    from agents.study.generalist import docs_tables

    root = Path(__file__).resolve().parents[1]
    page = (root / "docs" / "generalist.md").read_text(encoding="utf-8")
    shown = re.search(r"<!-- tables -->\n(.*?)\n<!-- end tables -->", page, re.DOTALL)
    assert shown, "docs/generalist.md lacks the <!-- tables --> ... <!-- end tables --> block"
    made = docs_tables(root / "results", root / "docs" / "results" / "ceilings.json",
                       root / "docs" / "results" / "procedural_ceilings.json", root / "docs" / "results" / "baselines.json")
    assert shown[1].strip() == made.strip(), "paste `python -m agents.study.generalist` into docs/generalist.md"
