"""fluidsim-sweep ``--address`` on a real Ray cluster, as docs/training.md's "On a cluster"
starts one: a head from ``ray start --head`` (here on 127.0.0.1 with 2 CPUs, token
authentication on, its token in a file of its own), a 2-seed sweep run against it to its
results table, and a sweep that would send no token, or a wrong one, refused in one line
before Ray connects. The head is stopped by its process id (``ray stop`` would stop every
Ray on this machine)."""

from __future__ import annotations

import csv
import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

pytest.importorskip("ray")

from fluidsim_envs.rl import sweep as sweep_cli  # noqa: E402
from tests.training.test_sweep import TINY  # noqa: E402

# Ray's environment: the test sets its own (RAY_ADDRESS would send `ray start` elsewhere)
RAY_VARS = ("RAY_AUTH_MODE", "RAY_AUTH_TOKEN", "RAY_AUTH_TOKEN_PATH", "RAY_ADDRESS")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def answers(port: int) -> bool:
    try:
        socket.create_connection(("127.0.0.1", port), timeout=1.0).close()
        return True
    except OSError:
        return False


class Head:
    """``ray start --head --block`` in a session of its own: its process id is the head's,
    and SIGTERM to it stops the head's processes (what is left of its session is killed)."""

    def __init__(self, root: Path) -> None:
        self.root, self.port = root, free_port()
        self.address = f"127.0.0.1:{self.port}"
        self.token = root / "token"
        self.token.write_text(secrets.token_hex(16))
        env = {k: v for k, v in os.environ.items() if k not in RAY_VARS}
        # the head's and the client's token: a file of the test's, not ~/.ray/auth_token
        self.env = {**env, "RAY_AUTH_MODE": "token", "RAY_AUTH_TOKEN_PATH": str(self.token)}
        # the ports Ray would otherwise take at fixed numbers (another Ray here may hold them)
        ports = ("dashboard-port", "ray-client-server-port", "dashboard-agent-listen-port")
        command = [sys.executable, "-m", "ray.scripts.scripts", "start", "--head", "--block"]
        command += ["--node-ip-address=127.0.0.1", f"--port={self.port}", "--num-cpus=2"]
        command += ["--include-dashboard=false", "--disable-usage-stats"]
        command += [f"--temp-dir={root / 'ray'}", "--object-store-memory=100000000"]
        command += [f"--{name}={free_port()}" for name in ports]
        self.log = (root / "head.log").open("w")
        self.process = subprocess.Popen(
            command, env=self.env, stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True
        )

    def wait_ready(self, timeout_s: float = 60.0) -> None:
        deadline = time.monotonic() + timeout_s
        while not answers(self.port):
            if self.process.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"the Ray head did not start:\n{self.text()}")
            time.sleep(0.2)

    def text(self) -> str:
        self.log.flush()
        return (self.root / "head.log").read_text()

    def stop(self) -> None:
        """SIGTERM to the head (``--block`` stops its processes on it), then SIGKILL to
        whatever of its session is left."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                pass
        try:
            os.killpg(self.process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass  # none left
        self.process.wait(timeout=10)
        self.log.close()


@pytest.fixture(scope="module")
def head():
    # short: Ray's socket paths under its temp dir must fit in a unix socket's 107 bytes
    root = Path(tempfile.mkdtemp(prefix="fsray", dir="/tmp"))
    started = Head(root)
    try:
        started.wait_ready()
        yield started
    finally:
        started.stop()
        shutil.rmtree(root, ignore_errors=True)


def sweep_argv(head: Head, folder: Path) -> list[str]:
    argv = ["paper_airplane_ppo", "--set", *TINY, "total_timesteps=2048", "--seeds", "2"]
    return [*argv, "--address", head.address, "--sweep-dir", str(folder)]


@pytest.mark.parametrize(
    ("env", "said"),
    [
        (
            {},
            "the Ray head there wants a token (Ray's token authentication): set RAY_AUTH_MODE"
            "=token where fluidsim-sweep runs",
        ),
        (
            {"RAY_AUTH_MODE": "token", "RAY_AUTH_TOKEN": "not-the-heads"},
            "the Ray head there refused this machine's token (from RAY_AUTH_TOKEN)",
        ),
        (
            {"RAY_AUTH_MODE": "token", "RAY_AUTH_TOKEN_PATH": "/nonexistent/token"},
            "RAY_AUTH_MODE=token is set here but no token was found (in RAY_AUTH_TOKEN or "
            "/nonexistent/token)",
        ),
    ],
)
def test_a_sweep_without_the_heads_token_is_refused_in_one_line(
    head, tmp_path, monkeypatch, capsys, env, said
):
    for name in RAY_VARS:
        monkeypatch.delenv(name, raising=False)
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    folder = tmp_path / "s"
    started = time.monotonic()
    assert sweep_cli.main(sweep_argv(head, folder)) == 2
    assert time.monotonic() - started < 10  # asked once, not Ray's retries
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(
        f"fluidsim-sweep: error: --address {head.address}: "
    )
    assert said in err and "ray get-auth-token" in err and "InvalidAuthToken" not in err
    assert not folder.exists()  # refused before anything was written


def test_a_two_seed_sweep_runs_on_the_cluster(head, tmp_path):
    """The console script in a process of its own, with the head's token (Ray caches its
    token and auth mode per process)."""
    folder = tmp_path / "s"
    script = "import sys; from fluidsim_envs.rl.cli import sweep; sys.exit(sweep())"
    done = subprocess.run(
        [sys.executable, "-c", script, *sweep_argv(head, folder)],
        env=head.env,
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "InvalidAuthToken" not in done.stderr
    assert f"on 2 CPUs, 1 per trial; into {folder}" in done.stdout
    with (folder / "results.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert sorted(int(r["seed"]) for r in rows) == [0, 1]
    for row in rows:
        assert row["status"] == "finished" and int(row["timesteps"]) == 2048, row
        assert (folder / row["run_dir"] / "model.safetensors").is_file()
    # the trials ran in the head's workers (its session's logs), not in an embedded Ray
    assert any((head.root / "ray").glob("session_*/logs/worker-*"))
