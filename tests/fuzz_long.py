"""The long fuzz run: mutated UFFs through ``identify`` and ``diagnose``, mutated meshes through ``props``.

    python tests/fuzz_long.py [--files 12000] [--seed 0] [--save FOLDER]

Each file is a seed (tests/mutations.py: the real exporters' files and meshes in tests/fixtures/,
the project's own exports) with 1-3 mutations, run through ``massline.cli.app.run`` — what the
``massline`` command runs — in this process, with ``--json OUT``. A run passes when it exits 0 or 2,
prints no traceback, no warning and no library text (file descriptors 1 and 2 are watched too), says
one line on stderr when it exits 2, and leaves OUT whole (exit 0) or absent (exit 2) with no
temporary file beside it. Failures are listed and, with ``--save``, their files kept.
"""

from __future__ import annotations

import argparse
import io
import json
import os
import random
import signal
import sys
import tempfile
import time
from collections import Counter
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

from mutations import FIXTURE_MESH_UNITS, fixture_meshes, fixture_uffs, mutate, own_meshes, own_uffs

from massline.cli.app import run

SHARES = (("identify", 0.45), ("diagnose", 0.2), ("props", 0.35))
HANG_SECONDS = 120
SLOW_SECONDS = 10.0  # a run this long is listed (not a failure)


class Hang(BaseException):
    """A run that took longer than HANG_SECONDS (a BaseException: the command must not catch it)."""


def _alarm(*_):
    raise Hang


class DescriptorCapture:
    """Whatever C code writes to file descriptors 1 and 2 (LAPACK's 'On entry to DLASCL', a library's printf)."""

    def __enter__(self):
        self.file = tempfile.TemporaryFile()
        self.saved = [os.dup(1), os.dup(2)]
        for fd in (1, 2):
            os.dup2(self.file.fileno(), fd)
        return self

    def __exit__(self, *_):
        for fd, saved in zip((1, 2), self.saved):
            os.dup2(saved, fd)
            os.close(saved)
        self.file.seek(0)
        self.text = self.file.read().decode("utf-8", "replace")
        self.file.close()


def command_line(command: str, path: Path, out: Path, units: str) -> list[str]:
    if command == "props":
        return ["props", str(path), "--units", units, "--density", "2700", "--json", str(out)]
    extra = ["--bootstrap", "20"] if command == "identify" else []
    return [command, str(path), *extra, "--json", str(out)]


def problems(code: int, stdout: str, stderr: str, chatter: str, out: Path) -> list[str]:
    """What is wrong with one run (empty: it behaved)."""
    found = []
    if code not in (0, 2):
        found.append(f"exit {code}: {stderr.strip()[:200]}")
    if "Traceback" in stdout + stderr + chatter:
        found.append("traceback")
    if chatter.strip():
        found.append(f"library text on fd 1/2: {chatter.strip()[:200]!r}")
    if code == 2 and (len(stderr.strip().splitlines()) != 1 or not stderr.startswith("massline")):
        found.append(f"exit 2 without one line: {stderr[:200]!r}")
    if code == 0 and stderr.strip():
        found.append(f"exit 0 with stderr: {stderr[:200]!r}")
    if code == 0:
        try:
            json.loads(out.read_text())
        except (OSError, ValueError):
            found.append("exit 0 without a whole --json file")
    if code != 0 and out.exists():
        found.append("a refused run left its --json file")
    if list(out.parent.glob(".*.tmp")):
        found.append("a temporary file was left")
    return found


def seeds(folder: Path) -> dict:
    """The seeds of each command; the own exports (which identify) as often as all the fixtures together."""
    own = own_uffs(folder)
    fixtures = fixture_uffs()
    uffs = [(p.suffix, p.read_bytes(), None) for p in fixtures + own * (len(fixtures) // len(own))]
    fixtures = [(p, FIXTURE_MESH_UNITS[p.name]) for p in fixture_meshes() if p.stat().st_size < 300_000]
    meshes = [(p.suffix, p.read_bytes(), units) for p, units in fixtures + own_meshes(folder)]
    return {"identify": uffs, "diagnose": uffs, "props": meshes}


def one_run(command: str, seed: tuple, rng: random.Random, folder: Path) -> tuple[int, list[str], list[str], bytes]:
    suffix, data, units = seed
    damaged, names = mutate(data, rng, rng.randint(1, 3))
    path, out = folder / f"input{suffix}", folder / "out" / "result.json"
    path.write_bytes(damaged)
    out.unlink(missing_ok=True)
    stdout, stderr = io.StringIO(), io.StringIO()
    signal.alarm(HANG_SECONDS)
    try:
        with DescriptorCapture() as fds, redirect_stdout(stdout), redirect_stderr(stderr):
            code = run(command_line(command, path, out, units), show_warnings=True)
    except Hang:
        code = -1
    finally:
        signal.alarm(0)
    chatter = fds.text if code != -1 else ""
    found = problems(code, stdout.getvalue(), stderr.getvalue(), chatter, out) if code != -1 else ["hang"]
    return code, found, names, damaged


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--files", type=int, default=12_000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--save", type=Path, help="keep the files of failing runs here")
    args = parser.parse_args()
    signal.signal(signal.SIGALRM, _alarm)
    rng = random.Random(args.seed)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "out").mkdir()
        pool = seeds(folder)
        exits, failures, slow, slowest = Counter(), [], [], (0.0, "")
        start = time.perf_counter()
        for k in range(args.files):
            command = rng.choices([c for c, _ in SHARES], [w for _, w in SHARES])[0]
            began = time.perf_counter()
            code, found, names, damaged = one_run(command, rng.choice(pool[command]), rng, folder)
            seconds = time.perf_counter() - began
            slowest = max(slowest, (seconds, f"{command} after {'+'.join(names)}"))
            exits[command, code] += 1
            if seconds > SLOW_SECONDS:
                slow.append((k, command, names, seconds))
                if args.save:
                    args.save.mkdir(parents=True, exist_ok=True)
                    (args.save / f"slow-{k}-{command}.bin").write_bytes(damaged)
            if found:
                failures.append((k, command, names, found))
                if args.save:
                    args.save.mkdir(parents=True, exist_ok=True)
                    (args.save / f"failure-{k}-{command}.bin").write_bytes(damaged)
            if (k + 1) % 500 == 0:
                print(f"{k + 1} files, {time.perf_counter() - start:.0f} s, {len(failures)} failures", flush=True)
    total = time.perf_counter() - start
    print(
        f"\n{args.files} mutated files in {total:.0f} s ({total / args.files * 1e3:.0f} ms each; "
        f"slowest {slowest[0]:.1f} s: {slowest[1]})"
    )
    for command, _ in SHARES:
        counts = {code: n for (c, code), n in sorted(exits.items()) if c == command}
        print(f"  {command:9s} {sum(counts.values()):6d} runs, exit codes {counts}")
    print(f"runs over {SLOW_SECONDS:g} s: {len(slow)}")
    for k, command, names, seconds in slow[:10]:
        print(f"  #{k} {command} after {'+'.join(names)}: {seconds:.1f} s")
    print(f"failures: {len(failures)}")
    for k, command, names, found in failures[:30]:
        print(f"  #{k} {command} after {'+'.join(names)}: {'; '.join(found)}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
