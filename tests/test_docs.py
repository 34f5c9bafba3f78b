"""The documentation: the site builds strictly, its Python examples run, its config paths exist.

README.md and the pages under docs/ are what a newcomer copies from, so their examples are
executed here: every ```python block of a file runs, in order, in one namespace, in a fresh
process started in the repository root. A block preceded by ``<!-- no-test -->`` is skipped
(an example that needs a display or hours of training); the marker is allowed on a few blocks
only. Shell blocks (```bash) are not run.
"""

from __future__ import annotations

import glob
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
NO_TEST = "<!-- no-test -->"
MAX_NO_TEST = 3
"""how many Python blocks in all may be skipped"""
EXAMPLE_TIMEOUT_S = 240
"""per file: its examples together (the first camera frame of a process alone takes ~20 s)"""
BUILD_TIMEOUT_S = 120

_FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<ticks>`{3,}|~{3,})(?P<info>.*)$")
_INCLUDE = re.compile(r"^<!-- include: (\S+) -->$", re.MULTILINE)
"""a page's include block (docs/_hooks/include_repo_files.py): on the site it shows that file"""
_CONFIG_PATH = re.compile(r"configs/[A-Za-z0-9_.*/-]+?\.yaml")
_PLACEHOLDER = re.compile(r"\.\.\.|\b[A-Z][A-Z_]+\b")


def doc_files() -> list[Path]:
    """README.md and every Markdown page of the site."""
    return [ROOT / "README.md", *sorted(DOCS.rglob("*.md"))]


def code_blocks(path: Path) -> list[dict]:
    """Every fenced block of a Markdown file: its language, first line number, source, and
    whether the line before the fence (blank lines skipped) is the no-test marker."""
    lines = path.read_text(encoding="utf-8").splitlines()
    blocks, i = [], 0
    while i < len(lines):
        opening = _FENCE.match(lines[i])
        if not opening:
            i += 1
            continue
        ticks, indent = opening["ticks"], len(opening["indent"])
        body, j = [], i + 1
        while j < len(lines) and not re.match(rf"^[ \t]*{re.escape(ticks[0])}{{{len(ticks)},}}\s*$", lines[j]):
            body.append(lines[j][indent:] if lines[j][:indent].strip() == "" else lines[j])
            j += 1
        before = next((lines[k].strip() for k in range(i - 1, -1, -1) if lines[k].strip()), "")
        language = (opening["info"].strip().split() or [""])[0].lstrip("{.").rstrip("}")
        blocks.append(dict(language=language, line=i + 2, source="\n".join(body), skipped=before == NO_TEST))
        i = j + 1
    return blocks


def python_blocks(path: Path) -> list[dict]:
    return [b for b in code_blocks(path) if b["language"] in ("python", "py")]


def _relative(path: Path) -> str:
    return str(path.relative_to(ROOT))


FILES_WITH_EXAMPLES = [p for p in doc_files() if any(not b["skipped"] for b in python_blocks(p))]

# Runs in a fresh interpreter: the blocks arrive as JSON on stdin and run in one namespace, each
# compiled under its file and line so a failure's traceback points into the Markdown file.
_RUNNER = """
import json, sys
namespace = {"__name__": "__main__"}
for block in json.load(sys.stdin):
    code = compile("\\n" * (block["line"] - 1) + block["source"], block["file"], "exec")
    exec(code, namespace)
"""


@pytest.mark.parametrize("path", FILES_WITH_EXAMPLES, ids=_relative)
def test_python_examples_run(path: Path, tmp_path: Path):
    """Every Python example of the file runs, top to bottom, as a reader would paste them."""
    blocks = [dict(b, file=_relative(path)) for b in python_blocks(path) if not b["skipped"]]
    env = dict(os.environ, MPLBACKEND="Agg", OMP_NUM_THREADS="1", TMPDIR=str(tmp_path))
    done = subprocess.run(
        [sys.executable, "-c", _RUNNER], input=json.dumps(blocks), cwd=ROOT, env=env,
        capture_output=True, text=True, timeout=EXAMPLE_TIMEOUT_S,
    )
    assert done.returncode == 0, f"an example of {_relative(path)} failed:\n{done.stderr[-4000:]}"


def test_no_test_marker_is_rare_and_marks_python_blocks():
    """Skipping is the exception: a few blocks at most, and the marker stands right before a
    Python block (a stray marker would silently skip nothing, or the wrong block)."""
    skipped = [(p, b) for p in doc_files() for b in python_blocks(p) if b["skipped"]]
    assert len(skipped) <= MAX_NO_TEST, "too many examples skip the test: " + ", ".join(
        f"{_relative(p)}:{b['line']}" for p, b in skipped)
    markers = sum(line.strip() == NO_TEST for p in doc_files() for line in p.read_text(encoding="utf-8").splitlines())
    assert markers == len(skipped), f"{markers - len(skipped)} '{NO_TEST}' marker(s) stand before no Python block"


def test_the_parser_finds_the_examples():
    """The example runner sees what a reader sees: README's gym.make example is a Python block."""
    readme = python_blocks(ROOT / "README.md")
    assert any("NumpyWrapper" in b["source"] and "gym.make" in b["source"] for b in readme)
    assert all(b["language"] != "bash" for b in readme)


def _shown_files() -> list[Path]:
    """README, the pages, and the repository files the pages include on the site."""
    shown = doc_files()
    for page in list(shown):
        shown += [ROOT / name for name in _INCLUDE.findall(page.read_text(encoding="utf-8"))]
    return shown


def test_config_paths_exist():
    """Every configs/...yaml path (or glob) that README or the site mentions names a file."""
    missing = []
    for path in _shown_files():
        assert path.is_file(), f"a page includes {_relative(path)}, which does not exist"
        for mention in sorted(set(_CONFIG_PATH.findall(path.read_text(encoding="utf-8")))):
            if _PLACEHOLDER.search(mention):  # configs/study/NAME.yaml, configs/...yaml: a pattern, not a path
                continue
            if not glob.glob(str(ROOT / mention)):
                missing.append(f"{_relative(path)}: {mention}")
    assert not missing, "config paths that name no file:\n" + "\n".join(missing)


def test_readme_links_and_size():
    """README.md stays a front page (at most 12 KB) whose relative links and pictures all
    resolve on GitHub, and it points to the documentation and to RESULTS.md."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(readme.encode("utf-8")) <= 12_000, "README.md is over 12 KB: move the detail to docs/"
    targets = re.findall(r"\]\(([^)\s]+)\)", readme)
    local = [t.split("#")[0] for t in targets if not re.match(r"^[a-z]+:", t) and not t.startswith("#")]
    assert {"docs/index.md", "RESULTS.md"} <= set(local)
    missing = [t for t in local if not (ROOT / t).exists()]
    assert not missing, f"README.md links to files that do not exist: {missing}"


def _modules() -> list[Path]:
    """Every module of the two packages (package __init__ files aside)."""
    return sorted(p for root in ("dynnav_tasks", "agents") for p in (ROOT / root).rglob("*.py")
                  if p.name != "__init__.py" and "__pycache__" not in p.parts)


def test_api_reference_covers_every_module():
    """A new module shows up in the API reference: each is named by a ``::: module`` line."""
    named = set(re.findall(r"^::: ([\w.]+)$", "\n".join(p.read_text(encoding="utf-8")
                                                       for p in (DOCS / "api").glob("*.md")), re.MULTILINE))
    missing = [".".join(p.relative_to(ROOT).with_suffix("").parts) for p in _modules()]
    missing = [m for m in missing if m not in named]
    assert not missing, "modules missing from docs/api/*.md (add a '::: module' line): " + ", ".join(missing)


def test_layout_page_matches_the_tree():
    """docs/layout.md names every tracked top-level folder, every sub-package and every module,
    and every folder it draws exists."""
    layout = (DOCS / "layout.md").read_text(encoding="utf-8")
    tree = layout.split("```text", 1)[1].split("```", 1)[0]
    drawn = re.findall(r"^\s*([\w.-]+)/", tree, re.MULTILINE)
    top = {p.name for p in ROOT.iterdir() if p.is_dir() and not p.name.startswith(".")}
    for folder in drawn:
        assert folder in top or any((ROOT / pkg / folder).is_dir() for pkg in ("dynnav_tasks", "agents")), \
            f"docs/layout.md draws {folder}/, which does not exist"
    packages = {p.parent.name for p in _modules()} - {"dynnav_tasks", "agents"}
    for folder in sorted(packages | {"assets", "benchmarks", "configs", "docs", "examples", "results", "scripts", "tests"}):
        assert folder in drawn, f"docs/layout.md's tree leaves out {folder}/"
    for module in _modules():
        assert f"`{module.name}`" in layout, f"docs/layout.md does not say what {module.relative_to(ROOT)} holds"


def test_site_builds_strictly(tmp_path: Path):
    """``mkdocs build --strict``: every page in the navigation, every link and picture found,
    every module the API pages name importable by mkdocstrings, every included file present."""
    mkdocs = shutil.which("mkdocs", path=str(Path(sys.executable).parent)) or shutil.which("mkdocs")
    assert mkdocs, "mkdocs is not installed: pip install -e '.[docs]' (scripts/setup.sh does)"
    site = tmp_path / "site"
    done = subprocess.run(
        [mkdocs, "build", "--strict", "--site-dir", str(site)], cwd=ROOT,
        env=dict(os.environ, NO_MKDOCS_2_WARNING="1"), capture_output=True, text=True, timeout=BUILD_TIMEOUT_S,
    )
    assert done.returncode == 0, f"mkdocs build --strict failed:\n{done.stdout[-3000:]}\n{done.stderr[-5000:]}"
    layout = (site / "layout" / "index.html").read_text(encoding="utf-8")
    assert "Where a change belongs" in layout
    api = (site / "api" / "agents-core" / "index.html").read_text(encoding="utf-8")
    assert "DQNLearner" in api, "the API pages hold no docstrings"
    results = (site / "results" / "index.html").read_text(encoding="utf-8")
    assert "<!-- include:" not in results and "<table>" in results, "the results page does not show RESULTS.md"
