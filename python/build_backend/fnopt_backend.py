"""fnopt's PEP 517 build backend: `pip install .` builds the extension with CMake and packs the
package `fnopt` into a wheel, with the standard library alone (no setuptools, nothing
downloaded), so that

    python3 -m venv --system-site-packages env
    env/bin/python -m pip install --no-build-isolation --no-index .

works offline on Debian's own Python, NumPy and SciPy.

The wheel holds python/fnopt (the .py files, the stub _fnopt.pyi, py.typed), the extension
_fnopt built for the Python running pip, and the shipped models as data under
share/fnopt/models of the environment: the module looks for them under share/fnopt of the
nearest directory above itself (util/installed_data.cpp), as after `cmake --install`.

The build directory is build-wheel/ in the source tree, kept between installs so that a second
one only relinks what changed, configured for the module alone (no MPI, no viewer, no tests).
FNOPT_BUILD_DIR names another one instead: an existing build tree is built as configured
(target _fnopt only), so that an install from a tree already built takes seconds.
"""
import base64
import hashlib
import io
import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import zipfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
NAME = "fnopt"
MODELS = ("fnopt-32.pt", "fnopt-multires.pt")
SUMMARY = "Cloth on regular grids, solved by classical and learned inner optimizers"


def _version():
    found = re.search(r"project\(fnopt VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not found:
        raise RuntimeError("no project(fnopt VERSION ...) in CMakeLists.txt")
    return found.group(1)


def _tag():
    """The wheel's tag for the running interpreter: cp311-cp311-linux_x86_64."""
    python = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{python}-{python}{sys.abiflags}-{platform}"


def _metadata():
    return (
        "Metadata-Version: 2.1\n"
        f"Name: {NAME}\n"
        f"Version: {_version()}\n"
        f"Summary: {SUMMARY}\n"
        "Requires-Python: >=3.9\n"
        "Requires-Dist: numpy\n"
        "Requires-Dist: scipy\n"
    )


def _run(command):
    print("fnopt build:", " ".join(str(c) for c in command), flush=True)
    subprocess.run([str(c) for c in command], check=True)


def _build_extension():
    """Configures (if needed) and builds the target _fnopt; returns the built extension's path."""
    build = ROOT / os.environ.get("FNOPT_BUILD_DIR", "build-wheel")  # relative to the source tree
    if not (build / "CMakeCache.txt").exists():
        # The interpreter a virtual environment was made from: the build directory outlives the
        # environment, and the extension needs only the interpreter's headers and ABI.
        python = os.path.realpath(getattr(sys, "_base_executable", sys.executable))
        configure = ["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DFNOPT_WITH_PYTHON=ON",
                     "-DFNOPT_WITH_MPI=OFF", "-DFNOPT_WITH_VIEWER=OFF", "-DBUILD_TESTING=OFF",
                     f"-DPython_EXECUTABLE={python}"]
        if shutil.which("ninja"):
            configure += ["-G", "Ninja"]
        _run(configure)
    _run(["cmake", "--build", build, "--target", "_fnopt"])
    extension = build / "python" / NAME / ("_fnopt" + sysconfig.get_config_var("EXT_SUFFIX"))
    if not extension.exists():
        raise RuntimeError(f"{extension} was not built: is {build} configured for this Python ({sys.executable})?")
    return extension


def _digest(data):
    return "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    """PEP 517: builds the extension and writes the wheel into `wheel_directory`.

    Parameters
    ----------
    wheel_directory : str
        Where the wheel goes.
    config_settings : dict, optional
        Unused.
    metadata_directory : str, optional
        Unused: the metadata is written afresh.

    Returns
    -------
    str
        The wheel's file name.
    """
    extension = _build_extension()
    version = _version()
    dist_info = f"{NAME}-{version}.dist-info"
    data = f"{NAME}-{version}.data/data"
    contents = []  # (name in the wheel, bytes)
    package = ROOT / "python" / NAME
    for path in sorted(package.iterdir()):
        if path.suffix in (".py", ".pyi") or path.name == "py.typed":
            contents.append((f"{NAME}/{path.name}", path.read_bytes()))
    contents.append((f"{NAME}/{extension.name}", extension.read_bytes()))
    for model in MODELS:
        contents.append((f"{data}/share/fnopt/models/{model}", (ROOT / "models" / model).read_bytes()))
    contents.append((f"{dist_info}/METADATA", _metadata().encode()))
    wheel = f"Wheel-Version: 1.0\nGenerator: fnopt_backend\nRoot-Is-Purelib: false\nTag: {_tag()}\n"
    contents.append((f"{dist_info}/WHEEL", wheel.encode()))
    record = "".join(f"{name},{_digest(blob)},{len(blob)}\n" for name, blob in contents)
    record += f"{dist_info}/RECORD,,\n"
    contents.append((f"{dist_info}/RECORD", record.encode()))

    filename = f"{NAME}-{version}-{_tag()}.whl"
    with zipfile.ZipFile(pathlib.Path(wheel_directory) / filename, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, blob in contents:
            info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
            info.external_attr = (0o755 if name.endswith(".so") else 0o644) << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(info, blob)
    return filename


def build_sdist(sdist_directory, config_settings=None):
    """PEP 517: the source distribution, the files git tracks.

    Parameters
    ----------
    sdist_directory : str
        Where the archive goes.
    config_settings : dict, optional
        Unused.

    Returns
    -------
    str
        The archive's file name.
    """
    files = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], check=True, capture_output=True).stdout
    base = f"{NAME}-{_version()}"
    filename = f"{base}.tar.gz"
    with tarfile.open(pathlib.Path(sdist_directory) / filename, "w:gz") as archive:
        for name in sorted(files.decode().split("\0")):
            if name and (ROOT / name).is_file():
                archive.add(ROOT / name, arcname=f"{base}/{name}")
        pkg_info = _metadata().encode()
        info = tarfile.TarInfo(f"{base}/PKG-INFO")
        info.size = len(pkg_info)
        archive.addfile(info, io.BytesIO(pkg_info))
    return filename


def get_requires_for_build_wheel(config_settings=None):
    """PEP 517: nothing beyond the standard library (CMake and a compiler come from the system).

    Parameters
    ----------
    config_settings : dict, optional
        Unused.

    Returns
    -------
    list of str
        No requirements.
    """
    return []


def get_requires_for_build_sdist(config_settings=None):
    """PEP 517: nothing beyond the standard library and git.

    Parameters
    ----------
    config_settings : dict, optional
        Unused.

    Returns
    -------
    list of str
        No requirements.
    """
    return []
