"""The env core's boundaries hold: no module reads another's private attributes (ManiSkill's
internals only through ``maniskill_adapter``), no caller guessing, one snapshot constructor."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CHECKED = sorted([*(ROOT / "dynnav_tasks").rglob("*.py"), *(ROOT / "agents" / "analysis").rglob("*.py")])
ADAPTER = ROOT / "dynnav_tasks" / "maniskill_adapter.py"


def _tree(path: Path) -> ast.AST:
    return ast.parse(path.read_text(), filename=str(path))


def _is_own(value: ast.expr) -> bool:
    """``self``, ``cls`` or ``super()``: an object's own attributes, or its base class's hooks."""
    if isinstance(value, ast.Name):
        return value.id in ("self", "cls")
    return isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id == "super"


def test_no_private_attribute_of_another_object_is_read():
    found = []
    for path in CHECKED:
        if path == ADAPTER:
            continue
        for node in ast.walk(_tree(path)):
            if (isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__")
                    and not _is_own(node.value)):
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {ast.unparse(node)}")
    assert found == []


def test_maniskill_internals_are_read_in_the_adapter_only():
    names = {node.attr for node in ast.walk(_tree(ADAPTER)) if isinstance(node, ast.Attribute)}
    assert {"_objs", "_bodies"} <= names
    for path in CHECKED:
        text = path.read_text()
        if path != ADAPTER:
            assert "._objs" not in text and "._bodies" not in text, path
        assert "_getframe" not in text, path


def _dataclass_replace_names(tree: ast.AST) -> set[str]:
    """How ``dataclasses.replace`` is called in a module (it builds a copy through ``__init__``)."""
    names = {"dataclasses.replace"}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module == "dataclasses":
            names |= {a.asname or a.name for a in node.names if a.name == "replace"}
    return names


def test_snapshots_are_built_in_snapshot_py_only():
    for path in CHECKED:
        if path.name == "snapshot.py":
            continue
        tree = _tree(path)
        copies = _dataclass_replace_names(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.Call):
                called = ast.unparse(node.func)
                where = f"{path.relative_to(ROOT)}:{node.lineno}"
                assert called.split(".")[-1] != "StepSnapshot", f"{where} builds a StepSnapshot"
                assert "StepSnapshot" not in [ast.unparse(a) for a in node.args], f"{where} builds a StepSnapshot"
                copied = ast.unparse(node.args[0]).lower() if node.args else ""
                assert not (called in copies and "snapshot" in copied), f"{where} copies a snapshot around snapshot_of"
