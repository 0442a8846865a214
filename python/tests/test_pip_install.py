"""`pip install .` offline into a virtual environment on Debian's own Python: the package comes
from the wheel the in-tree backend builds (pyproject.toml), with its stub and models, and runs
there as the build tree's module does.

The backend reuses the build tree the tested module comes from (FNOPT_BUILD_DIR), so the
extension is not compiled a second time; the installed files still come only from the wheel."""
import importlib.util
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import fnopt

ROOT = pathlib.Path(__file__).resolve().parents[2]

pytestmark = [
    pytest.mark.skipif(importlib.util.find_spec("ensurepip") is None,
                       reason="no ensurepip for `python3 -m venv` (Debian's python3-venv is not installed)"),
    pytest.mark.skipif(importlib.util.find_spec("pip") is None,
                       reason="no pip for this Python (Debian's python3-pip is not installed)"),
]

RUN_IN_VENV = """
import sys
import numpy as np
import fnopt
print(fnopt.__file__)
print(fnopt.shipped_model_path())
rollout = fnopt.run_rollout(fnopt.Scene(res=8, frames=2), optimizer="pqn")
print(repr(rollout))
np.save(sys.argv[1], rollout.positions)
learned = fnopt.run_rollout(fnopt.Scene(res=8, frames=2), optimizer="fnopt-ss", iters=3)
print(learned.optimizer_settings)
"""


def build_tree():
    """The build tree of the module under test (build/python/fnopt), if it is one."""
    build = pathlib.Path(fnopt.__file__).resolve().parents[2]
    return build if (build / "CMakeCache.txt").exists() else None


def test_pip_install_into_a_venv_gives_a_working_package(tmp_path):
    env_dir = tmp_path / "env"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(env_dir)], check=True)
    python = env_dir / "bin" / "python"
    environment = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "FNOPT_BUILD_DIR")}
    environment.update(PIP_NO_INPUT="1", PIP_DISABLE_PIP_VERSION_CHECK="1", OMP_WAIT_POLICY="PASSIVE",
                       OMP_NUM_THREADS="1")
    if build_tree():
        environment["FNOPT_BUILD_DIR"] = str(build_tree())
    install = subprocess.run([python, "-m", "pip", "install", "--no-build-isolation", "--no-index", str(ROOT)],
                             env=environment, capture_output=True, text=True)
    assert install.returncode == 0, install.stdout + install.stderr
    assert "Successfully installed fnopt-" + fnopt.__version__ in install.stdout

    site = pathlib.Path(subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_path('platlib'))"],
                                       env=environment, capture_output=True, text=True, check=True).stdout.strip())
    for name in ("__init__.py", "records.py", "_fnopt.pyi", "py.typed"):
        assert (site / "fnopt" / name).is_file(), name

    positions = tmp_path / "positions.npy"
    run = subprocess.run([python, "-c", RUN_IN_VENV, str(positions)], cwd=tmp_path, env=environment,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    module, model, rollout, learned = run.stdout.splitlines()
    assert pathlib.Path(module) == site / "fnopt" / "__init__.py"
    assert pathlib.Path(model) == env_dir / "share" / "fnopt" / "models" / "fnopt-32.pt"
    assert learned.startswith("fnopt-ss: model=" + str(env_dir / "share" / "fnopt" / "models" / "fnopt-multires.pt"))
    here = fnopt.run_rollout(fnopt.Scene(res=8, frames=2), optimizer="pqn")
    assert rollout == repr(here)
    assert np.array_equal(np.load(positions), here.positions)
