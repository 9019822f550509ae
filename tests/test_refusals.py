"""Every command × every numeric option's invalid values, and every output-path fault: exit 2 at once.

Each case runs the command line in this process (``massline.cli.app.run``, what the ``massline`` entry point
runs, with warnings shown as stderr lines) and asserts: exit code 2 within 2 s of CPU time (the process's own,
which other work on the machine does not stretch as it does the wall clock), exactly one line on stderr
naming the option (and for numbers the allowed range), nothing on stdout, nothing written. A handful of
cases run through the real entry point in a subprocess at the end.
"""

import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import pytest
from mutations import own_uffs

from massline.cli.app import run
from massline.placement.hand_layouts import structure_exciters, structure_sensors

NAN, INF = "nan", "inf"
RANGE = ("≤", "<", "finite")
# option → invalid values, per command; each value is refused for its range (or its meaning)
NUMBERS = {
    "props": {"--density": ["-1", "0", NAN, INF, "-inf", "1e300", "2.7"], "--mass": ["-1", "0", NAN, INF, "1e9"]},
    "plan": {
        "--sensors": ["-1", "1.5", NAN, INF, "1e9"],
        "--exciters": ["-1", NAN, INF, "1e9"],
        "--triaxial": ["-1", NAN, INF, "1e9"],
        "--candidates": ["0", "-5", NAN, INF, "1e9", "1e12"],
        "--edge-keepout": ["-1", NAN, INF],
        "--noise-relative": ["-0.1", "0", NAN, INF, "5"],
        "--noise-floor": ["-0.1", NAN, INF, "5"],
        "--seed": ["-1", NAN, INF, "1e30"],
        "--exclude-faces": ["-1", NAN],
        "--sensor-base": ["-1", NAN, INF, "1e9"],
        "--tip": ["-1", NAN, INF, "1e9"],
        "--density": ["-1", "0", NAN, INF],
        "--mass": ["-1", "0", NAN, INF],
    },
    "simulate": {
        "--seed": ["-1", NAN, "1e30"],
        "--noise": ["-0.1", NAN, INF, "5"],
        "--noise-floor": ["-0.1", NAN, INF, "5"],
        "--sensor-mass": ["-1", NAN, INF, "1e9"],
        "--impact": ["-1", "0", NAN, INF, "1e6"],
        "--averages": ["0", "-1", NAN, INF, "1e9"],
        "--fmax": ["0", "-1", NAN, INF, "1e12"],
        "--lines": ["0", "-1", NAN, INF, "1e9"],
        "--modes": ["0", "-1", NAN, INF, "1e9"],
        "--fe-size": ["0", "-1", NAN, INF, "1e3"],
        "--material": ["0,0.3", "nan,0.3", "70e9,inf", "70e9,0.6", "1e300,0.3"],
        "--effect": ["sensor_gain=nan@3", "sensor_gain=inf@3", "transverse_sensitivity=-inf@all"],
        "--suspension": ["cord:k=-1", "cord:k=nan", "cord:L=inf", "cord:L=0", "cord:loss=-0.1", "cord:at=nan;0;0"],
    },
    "identify": {
        "--transverse": ["-1", NAN, INF, "5"],
        "--bootstrap": ["-3", NAN, INF, "1e9"],
        "--sensor-mass": ["-1", NAN, INF],
        "--density": ["-1", "0", NAN, INF],
        "--mass": ["-1", "0", NAN, INF],
        "--weighed-mass": ["-1", "0", NAN, INF, "4±-1", "4±nan"],
        "--calibration": ["-1", NAN, INF, "30", "1,2,3", "1,-2", "abc"],
        "--sensor-mass-tolerance": ["-1", NAN, INF, "0.5"],
        "--band": ["-1 40", "0 40", "nan 40", "5 inf", "40 5", "5 1e12"],
        "--suspension": ["cord:k=-1", "cord:k=nan", "cord:L=0", "foam:k=inf", "foam:shear=-1", "cord:at=nan;0;0"],
        "--material": ["0,0.3", "nan,0.3", "70e9,0.6"],
    },
    "diagnose": {
        "--transverse": ["-1", NAN, INF, "5"],
        "--band": ["-1 40", "nan 40", "40 5", "5 inf"],
        "--density": ["-1", "0", NAN, INF],
        "--mass": ["-1", "0", NAN, INF],
        "--suspension": ["cord:k=0", "foam:loss=-1"],
        "--material": ["1e300,0.3"],
    },
    "demo": {"--seed": ["-1", NAN, INF, "1e30"]},
}
# a whole option group given invalid: (command, option, values)
GROUPS = [
    ("plan", "--exclude-box", "0 0 0 nan 1 1"),
    ("plan", "--fixed-sensor", "0 0 inf 1 0 0"),
    ("plan", "--fixed-exciter", "0 0 0 1 0 -inf"),
    ("plan", "--fixed-sensor", "0 0 0 1 0 -1e999"),
]
# refused after parsing, before any work: (command, extra arguments, option, words)
MEANINGS = [
    ("simulate", ["--sensor-mass", "5"], "--sensor-mass", "as much as the body"),
    ("simulate", ["--fe-size", "1e-5"], "--fe-size", "degrees of freedom"),
    ("identify", ["--mesh", "structure", "--density", "nan"], "--density", "value"),
    ("identify", ["--suspension", "cord"], "--suspension", "needs --mesh"),
    ("diagnose", ["--suspension", "foam"], "--suspension", "needs --mesh"),
    ("identify", ["--mesh", "structure", "--material", "steel"], "--material", "give --suspension"),
]


@pytest.fixture(scope="module")
def inputs(tmp_path_factory) -> dict:
    """A plan of the bundled structure and a small recording of it, in a folder of their own."""
    folder = tmp_path_factory.mktemp("inputs")
    lines = lambda ls: [{"point": p.tolist(), "direction": d.tolist()} for p, d in zip(ls.points, ls.directions)]  # noqa: E731
    plan = {"mesh": "structure", "units": "m", "density": 7850.0}
    plan |= {"sensors": lines(structure_sensors()), "exciters": lines(structure_exciters())}
    (folder / "plan.json").write_text(json.dumps(plan))
    uff = own_uffs(folder)[0]
    return {"plan": folder / "plan.json", "uff": uff, "folder": folder}


def base(command: str, inputs: dict, out: Path) -> list[str]:
    """A valid command line writing into ``out`` (a folder)."""
    return {
        "props": ["props", "structure", "--json", str(out / "p.json")],
        "plan": ["plan", "structure", "--out", str(out / "plan")],
        "simulate": ["simulate", str(inputs["plan"]), "--rigid", "--out", str(out / "t.uff")],
        "report": ["report", str(inputs["plan"]), "--out", str(out / "r.html")],
        "identify": ["identify", str(inputs["uff"]), "--json", str(out / "i.json")],
        "diagnose": ["diagnose", str(inputs["uff"]), "--json", str(out / "d.json")],
        "demo": ["demo", "--out", str(out / "demo")],
    }[command]


def tree(*folders: Path) -> dict:
    """Every file under ``folders`` with its size and modification time, every folder (a folder's time changes
    when the writability probe's file comes and goes)."""
    return {p: p.is_dir() or (p.stat().st_size, p.stat().st_mtime_ns) for f in folders for p in sorted(f.rglob("*"))}


def refused(argv: list[str], capsys, *watched: Path) -> str:
    """Run ``argv``; assert exit 2 within 2 s of CPU time, one stderr line, no stdout, nothing written; return the
    line."""
    before = tree(*watched)
    start = time.process_time()
    code = run(argv, show_warnings=True)
    seconds = time.process_time() - start
    out, err = capsys.readouterr()
    assert code == 2, (argv, out, err)
    assert seconds < 2.0, (argv, seconds)
    assert out == "" and len(err.splitlines()) == 1 and err.startswith("massline"), (argv, out, err)
    assert tree(*watched) == before, argv
    return err


def numeric_cases():
    for command, options in NUMBERS.items():
        for option, values in options.items():
            for value in values:
                yield pytest.param(command, option, value.split(), id=f"{command} {option} {value}")
    for command, option, values in GROUPS:
        yield pytest.param(command, option, values.split(), id=f"{command} {option} {values}")


@pytest.mark.parametrize("command,option,values", list(numeric_cases()))
def test_an_invalid_number_is_refused_with_its_range(command, option, values, inputs, tmp_path, capsys):
    argv = base(command, inputs, tmp_path)
    if command in ("identify", "diagnose") and option in ("--density", "--mass", "--suspension", "--material"):
        argv += ["--mesh", "structure"] + (["--suspension", "cord"] if option == "--material" else [])
    if option == "--material" and command == "simulate":
        argv.remove("--rigid")  # a rigid body's test reads no material
    line = refused([*argv, option, *values], capsys, tmp_path, inputs["folder"])
    assert option in line and any(sign in line for sign in RANGE), line


@pytest.mark.parametrize("command,extra,option,words", MEANINGS, ids=[" ".join(m[1]) for m in MEANINGS])
def test_a_meaningless_value_is_refused_before_the_work(command, extra, option, words, inputs, tmp_path, capsys):
    line = refused([*base(command, inputs, tmp_path), *extra], capsys, tmp_path, inputs["folder"])
    assert option in line and words in line, line


# command → its output options, each: (option, a file name in the folder, whether it is a folder)
OUTPUTS = {
    "props": [("--json", "p.json", False)],
    "plan": [("--out", "plan", True)],
    "simulate": [("--out", "t.uff", False), ("--plot", "t.png", False)],
    "report": [("--out", "r.html", False)],
    "identify": [("--json", "i.json", False), ("--report", "i.html", False)],
    "diagnose": [("--json", "d.json", False), ("--plot", "d.png", False), ("--report", "d.html", False)],
    "demo": [("--out", "demo", True)],
}


def read_only_folder(tmp_path: Path) -> Path:
    """A folder no file can be created in: a tmp folder without write permission, or (for root, whom
    permissions do not stop) /sys."""
    folder = tmp_path / "read-only"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        (folder / "probe").touch()
    except PermissionError:
        return folder
    (folder / "probe").unlink()
    return Path("/sys")


def fault(kind: str, folder: Path, name: str, is_folder: bool, tmp_path: Path) -> tuple[Path, bool]:
    """Make the fault; return the path to give and whether --force is passed."""
    if kind == "read-only folder":
        return read_only_folder(tmp_path) / name, True
    target = folder / name
    if kind == "a folder where a file goes":
        (target / "plan.json" if is_folder else target).mkdir(parents=True)
        return target, True
    if kind == "a file where a folder goes":
        target.write_text("precious")
        return target, True
    (target / "plan.json" if is_folder else target).parent.mkdir(parents=True, exist_ok=True)
    (target / "plan.json" if is_folder else target).write_text("precious")
    return target, False


def path_cases():
    for command, outputs in OUTPUTS.items():
        for option, name, is_folder in outputs:
            kinds = ["read-only folder", "a folder where a file goes", "an existing file without --force"]
            kinds += ["a file where a folder goes"] if is_folder else []
            for kind in kinds:
                yield pytest.param(command, option, name, is_folder, kind, id=f"{command} {option}: {kind}")


@pytest.mark.parametrize("command,option,name,is_folder,kind", list(path_cases()))
def test_an_output_path_fault_is_refused_before_the_work(
    command, option, name, is_folder, kind, inputs, tmp_path, capsys
):
    work = tmp_path / "work"
    work.mkdir()
    path, force = fault(kind, work, name, is_folder, tmp_path)
    argv = base(command, inputs, work)
    if option in argv:
        argv[argv.index(option) + 1] = str(path)
    else:
        argv += [option, str(path)]
    line = refused(argv + (["--force"] if force else []), capsys, work, inputs["folder"])
    assert str(path) in line or str(path / "plan.json") in line, line
    assert "--force" in line if kind.startswith("an existing file") else True


def test_planner_memory_is_estimated_before_anything_is_allocated():
    from massline.core.errors import MasslineError
    from massline.cli.plan import check_memory

    check_memory(400, False, available=1e9)
    with pytest.raises(MasslineError, match=r"--candidates 1000000: .* about 5\.2 GB .* 2\.0 GB .* give --candidates"):
        check_memory(1_000_000, False, available=2e9)


def test_output_that_is_not_a_terminal_is_not_wrapped():
    import io

    from massline.cli.output import console_for

    stream = io.StringIO()
    sentence = "a sentence and a path /a/long/folder/name/" + "x" * 150 + ".uff that a pipe gets whole"
    console_for(stream).print(sentence)
    assert stream.getvalue() == sentence + "\n"


def children_cpu_seconds() -> float:
    """The CPU time (user + system, s) of this process's finished children."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


SUBPROCESS = [
    ["simulate", "{plan}", "--lines", "0", "--out", "{work}/t.uff"],
    ["identify", "{uff}", "--transverse", "-1"],
    ["props", "structure", "--json", "{read_only}/p.json"],
    ["identify", "{uff}", "--report", "{work}", "--force"],
    ["plan", "structure", "--candidates", "1e9"],
]


@pytest.mark.parametrize("args", SUBPROCESS, ids=[" ".join(a[:3]) for a in SUBPROCESS])
def test_the_real_entry_point_refuses_in_one_line(args, inputs, tmp_path):
    work = tmp_path / "work"
    work.mkdir()
    names = {"plan": inputs["plan"], "uff": inputs["uff"], "work": work, "read_only": read_only_folder(tmp_path)}
    argv = [a.format(**names) for a in args]
    env = {**os.environ, "MASSLINE_DEBUG": "1"}  # warnings and tracebacks shown: any would break the one line
    start = children_cpu_seconds()
    done = subprocess.run([sys.executable, "-m", "massline", *argv], capture_output=True, text=True, env=env)
    assert done.returncode == 2 and done.stdout == "", done
    assert len(done.stderr.splitlines()) == 1 and "Traceback" not in done.stderr, done.stderr
    assert children_cpu_seconds() - start < 10  # the imports take ~1 s of CPU
    assert list(work.iterdir()) == []


@pytest.mark.parametrize("command", [[], *([c] for c in NUMBERS), ["report"]], ids=lambda c: " ".join(c) or "massline")
def test_help_speaks_to_users(command, capsys):
    assert run([*command, "--help"], show_warnings=True) == 0
    out, err = capsys.readouterr()
    assert err == "" and out.startswith("usage: massline") and "``" not in out and ":mod:" not in out
