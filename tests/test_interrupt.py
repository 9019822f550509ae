"""Ctrl-C at any moment, also while the modules load, ends with one line and exit code 130 (after the plain
progress lines a command off a terminal prints on stderr until then).

The interpreter's own start comes before any of massline runs (about 30 ms, several times that on a loaded
machine): each delay is counted from its end, timed on a bare interpreter just before."""

import os
import re
import signal
import subprocess
import sys
import time

import pytest


def terminal_like():
    """Ctrl-C as at a terminal: a test runner started in the background may pass SIGINT on ignored."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def interpreter_start() -> float:
    """Seconds a bare interpreter takes to start and end here, now."""
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", "pass"], check=True)
    return time.perf_counter() - start


@pytest.mark.parametrize(
    "after", [0.1, 0.3, 0.6, 3.0], ids=["importing numpy", "importing", "importing trimesh", "planning"]
)
def test_ctrl_c_says_interrupted_and_exits_130(tmp_path, after):
    env = {**os.environ, "MASSLINE_DEBUG": "1"}
    after += interpreter_start()
    command = [sys.executable, "-m", "massline", "plan", "structure", "--candidates", "20000", "--out", tmp_path / "p"]
    process = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, preexec_fn=terminal_like
    )
    time.sleep(after)
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=60)
    assert process.returncode == 130, (out, err)
    *progress, last = err.strip().splitlines()
    assert last == "massline: interrupted" and "Traceback" not in out + err
    assert all(re.match(r"\[ *[\d.]+ s\] ", line) for line in progress), err  # off a terminal: plain progress lines
    assert not (tmp_path / "p").exists()
