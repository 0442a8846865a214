"""Shared fixtures: the command-line binary (FNOPT_BINARY, set by CTest) and small scenes."""
import os
import subprocess

import pytest

import fnopt


@pytest.fixture(scope="session")
def fnopt_binary():
    path = os.environ.get("FNOPT_BINARY")
    if not path:
        pytest.skip("FNOPT_BINARY is not set (run under CTest)")
    return path


@pytest.fixture
def run_cli(fnopt_binary):
    """Runs `fnopt ARGS...` and returns the CompletedProcess (text output)."""

    def run(*args):
        env = dict(os.environ, OMP_WAIT_POLICY="PASSIVE")
        return subprocess.run([fnopt_binary, *args], capture_output=True, text=True, env=env)

    return run


@pytest.fixture(autouse=True)
def one_thread():
    fnopt.set_threads(1)
