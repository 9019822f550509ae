"""The repository's layout (DESIGN.md): no command imports another, the kernel imports nothing else of the
project, and the package root re-exports the public API without loading it."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

CLI = Path(__file__).resolve().parents[1] / "massline" / "cli"
COMMANDS = {
    "props_command",
    "plan",
    "simulate",
    "report_command",
    "setup_command",
    "identify_command",
    "diagnose_command",
    "demo",
}
STAGES = ("placement", "identify", "virtual", "uff", "reports", "meshes", "export")


def imported_modules(path: Path, package: str = "massline.cli") -> set[str]:
    """The ``massline.*`` modules a file of ``package`` imports (top level and inside functions; relative imports
    resolved against ``package``), and the names taken from a package itself as ``PACKAGE.NAME``."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            module = package + (f".{node.module}" if node.module else "") if node.level else node.module or ""
            found.add(module)
            found |= {f"{module}.{a.name}" for a in node.names}
    return {m for m in found if m == "massline" or m.startswith("massline.")}


def test_the_commands_are_all_known():
    """Every module that defines a command's ``run`` is in COMMANDS, so the next test covers it."""
    runs = {p.stem for p in CLI.glob("*.py") if "\ndef run(" in p.read_text()} - {"app"}
    assert runs == COMMANDS


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_no_command_imports_another(command):
    others = {f"massline.cli.{c}" for c in COMMANDS - {command}}
    taken = imported_modules(CLI / f"{command}.py") & others
    assert not taken, f"massline.cli.{command} imports the commands {sorted(taken)}: move what they share to a library"


def test_importing_the_kernel_loads_no_other_stage():
    """``import massline.core`` in a fresh interpreter: ``massline`` (massline/__init__.py, its parent) and the
    kernel, nothing of placement, identify, virtual, uff, reports or meshes."""
    probe = "import sys, massline.core; print('\\n'.join(sorted(m for m in sys.modules if m.startswith('massline'))))"
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    loaded = run.stdout.split()
    assert "massline.core" in loaded
    stray = [m for m in loaded if m.split(".")[1:2] and m.split(".")[1] in STAGES]
    assert not stray, f"importing massline.core loaded {stray}"
    assert set(loaded) <= {"massline"} | {m for m in loaded if m.startswith("massline.core")}, loaded


def test_the_root_re_exports_the_public_api_lazily():
    """``import massline`` loads nothing else; each public name comes from its stage when first asked for."""
    probe = (
        "import sys, massline; before = sorted(m for m in sys.modules if m.startswith('massline'));"
        "from massline import identify_recording, diagnose_recording, plan_test, simulate_test, demo_story;"
        "from massline import build_placement_report, __version__;"
        "from massline.identify import identify_recording as same;"
        "print(before, identify_recording is same, identify_recording.__module__, simulate_test.__module__)"
    )
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert run.stdout.split() == [
        "['massline']",
        "True",
        "massline.identify.pipeline",
        "massline.virtual.simulation",
    ]


def test_every_public_name_resolves():
    import massline

    for name in massline.__all__:
        assert getattr(massline, name) is not None, name
    with pytest.raises(AttributeError):
        massline.no_such_name  # noqa: B018
