#!/usr/bin/env python3
"""Checks docs/design.md §1's table of folders against the tree, so that the table and the tree
cannot drift apart. The rule:

- every folder of src/fnopt (recursively) has a row: its own (`studies/compare/`) or its module's
  (`viewer/`, which then covers `viewer/web/`); and every row's path is a folder, under src/fnopt
  for a module (`metrics/`), else under the repository's root (`app/`, `python/`, `models/`);
- a row's files are named in it: each C++ file (.hpp, .cpp) of its module folder, and of its
  subfolders that have no row of their own, by its stem in backticks (`obstacle_distance`), once
  for a header and its source; `app/`'s row names app/*.cpp and app/*.hpp, `python/`'s names
  python/src/*.cpp, python/src/*.hpp and python/examples/*.py. So a file added without a word in
  the table fails;
- in those rows, a backticked lower-case word (letters, digits, underscores, optionally a path
  below the row's folder and an extension) names a file of the row, and must: a name left behind by
  a removed or renamed file fails too. A backticked path with a slash may instead name a file
  under src/fnopt (`simulation/rollout_file.hpp`), and one ending in a slash a folder (`web/`), which
  must exist. Anything else in backticks (`--resume`, `fnopt view`, `METHOD-interpK`, `resolve()`)
  is prose.

    scripts/check-layout-table.py [ROOT]     check the tree at ROOT (default: this repository)
    scripts/check-layout-table.py --self-test   check that planted drift of each kind is caught

Exit status 0 when the table and the tree agree; 1 with one line per problem.
"""
import pathlib
import re
import sys
import tempfile

CODE = re.compile(r"`([^`]+)`")
FILE_NAME = re.compile(r"^(?:[a-z0-9_]+/)*[a-z0-9_]+(?:\.(?:hpp|cpp|py))?$")
FOLDER_NAME = re.compile(r"^(?:[a-z0-9_.-]+/)+$")
CPP = (".hpp", ".cpp")
# Rows outside src/fnopt whose files are named, and where their files are: (folder, suffixes).
TOP_LEVEL_FILES = {
    "app/": (("app", CPP),),
    "python/": (("python/src", CPP), ("python/examples", (".py",))),
}


def table_rows(design: pathlib.Path) -> list:
    """(path, contents) per row of the table in design.md's section "## 1. Layout"."""
    rows, in_section = [], False
    for line in design.read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            in_section = line.startswith("## 1. ")
            continue
        if not in_section or not line.startswith("|"):
            continue
        cells = [cell.strip() for cell in line.strip().strip("|").split("|", 1)]
        match = re.fullmatch(r"`([^`]+/)`", cells[0])
        if match and len(cells) == 2:
            rows.append((match.group(1), cells[1]))
    if not rows:
        raise SystemExit(f"check-layout-table: {design}: no table of folders in '## 1. Layout'")
    return rows


def row_files(folder: pathlib.Path, suffixes, owned) -> list:
    """The files a row names: those of `folder` and of its subfolders that `owned` gives to it."""
    return sorted(p for p in folder.rglob("*") if p.is_file() and p.suffix in suffixes and owned(p.parent))


def named(contents: str) -> list:
    return [token for token in CODE.findall(contents) if FILE_NAME.match(token) or FOLDER_NAME.match(token)]


def check_names(root: pathlib.Path, label: str, contents: str, files: list, bases: list,
                row_folder: pathlib.Path) -> list:
    """The row's files against the names in its text; `bases` are the folders file names are relative
    to, `row_folder` the row's own folder (folder names are relative to it)."""
    found = []
    src = root / "src" / "fnopt"
    keys = {}
    for path in files:
        base = next(b for b in bases if b in path.parents)
        relative = path.relative_to(base).with_suffix("").as_posix()
        keys.setdefault(relative, []).append(path)
    stems = {}
    for relative in keys:
        stems.setdefault(relative.rsplit("/", 1)[-1], []).append(relative)
    mentioned = set()
    for token in named(contents):
        if token.endswith("/"):
            if not any((base / token).is_dir() for base in [row_folder, src, root]):
                found.append(f"design.md §1, row `{label}`: `{token}` is no folder")
            continue
        key = re.sub(r"\.(hpp|cpp|py)$", "", token)
        if key in keys:
            mentioned.add(key)
        elif "/" not in key and key in stems:
            mentioned.update(stems[key])
        elif "/" in token and (src / token).is_file():
            continue  # a file of another module, named as a cross-reference
        else:
            where = ", ".join(b.relative_to(root).as_posix() + "/" for b in bases)
            found.append(f"design.md §1, row `{label}`: `{token}` names no file of {where}")
    for key in sorted(keys):
        if key not in mentioned:
            path = min(keys[key], key=lambda p: p.suffix != ".hpp").relative_to(root).as_posix()
            stem = key.rsplit("/", 1)[-1]
            found.append(f"design.md §1, row `{label}`: {path} is not named (`{stem}`)")
    return found


def problems(root: pathlib.Path) -> list:
    rows = table_rows(root / "docs" / "design.md")
    src = root / "src" / "fnopt"
    found, modules, seen = [], {}, set()
    for path, contents in rows:
        if path in seen:
            found.append(f"design.md §1: two rows for `{path}`")
        seen.add(path)
        if (src / path).is_dir():
            modules[path.rstrip("/")] = contents
        elif not (root / path).is_dir():
            found.append(f"design.md §1: row `{path}` is no folder (neither src/fnopt/{path} nor {path})")
    folders = sorted(p.relative_to(src).as_posix() for p in src.rglob("*") if p.is_dir())

    def row_of(folder: str):
        """The row that covers a folder of src/fnopt: its own, else its nearest parent's."""
        parts = folder.split("/")
        for n in range(len(parts), 0, -1):
            if "/".join(parts[:n]) in modules:
                return "/".join(parts[:n])
        return None

    for folder in folders:
        if row_of(folder) is None:
            found.append(f"design.md §1: src/fnopt/{folder}/ has no row (nor has its module)")
    for module, contents in modules.items():
        base = src / module
        files = row_files(base, CPP, lambda parent: row_of(parent.relative_to(src).as_posix()) == module)
        found += check_names(root, module + "/", contents, files, [base], base)
    for path, contents in rows:
        if path in TOP_LEVEL_FILES and path.rstrip("/") not in modules:
            bases = [root / folder for folder, _ in TOP_LEVEL_FILES[path]]
            files = []
            for base, (_, suffixes) in zip(bases, TOP_LEVEL_FILES[path]):
                if base.is_dir():
                    files += sorted(p for p in base.iterdir() if p.is_file() and p.suffix in suffixes)
            found += check_names(root, path, contents, files, bases, root / path)
    return found


def self_test() -> int:
    """A small tree whose table agrees must pass; each kind of drift planted in it must be caught."""
    table = ("## 1. Layout\n\n| directory | contents |\n|---|---|\n"
             "| `app/` | the command line (`main`, `run_command`), `--help` |\n"
             "| `cloth/` | the grid (`grid`), kernels (`stretch_kernel`), its page (`web/`), as `simulation/rollout.hpp` |\n"
             "| `simulation/` | the rollout (`rollout`) |\n"
             "| `python/` | `src/` the bindings (`scene`), `examples/` (`fit`) |\n"
             "\n## 2. The energy\n\n| `energy/` | not a row of §1 |\n")

    def tree(root: pathlib.Path) -> None:
        (root / "docs").mkdir()
        (root / "docs" / "design.md").write_text(table)
        for path in ("app/main.cpp", "app/run_command.cpp", "app/run_command.hpp", "src/fnopt/cloth/grid.hpp",
                     "src/fnopt/cloth/grid.cpp", "src/fnopt/cloth/stretch_kernel.hpp", "src/fnopt/cloth/web/page.js",
                     "src/fnopt/simulation/rollout.hpp", "python/src/scene.cpp", "python/examples/fit.py",
                     "python/tests/test_scene.py"):
            (root / path).parent.mkdir(parents=True, exist_ok=True)
            (root / path).write_text("\n")

    plants = {
        "a header not named": (lambda r: (r / "src/fnopt/simulation/rollout_file.hpp").write_text("\n"),
                               "rollout_file.hpp is not named"),
        "a binding not named": (lambda r: (r / "python/src/adjoint.cpp").write_text("\n"), "adjoint.cpp is not named"),
        "an example not named": (lambda r: (r / "python/examples/identify.py").write_text("\n"),
                                 "identify.py is not named"),
        "a subcommand not named": (lambda r: (r / "app/view_command.cpp").write_text("\n"),
                                   "view_command.cpp is not named"),
        "a file of a subfolder not named": (
            lambda r: ((r / "src/fnopt/cloth/kernels").mkdir(), (r / "src/fnopt/cloth/kernels/bend.hpp").write_text("\n")),
            "cloth/kernels/bend.hpp is not named"),
        "a stale name": (lambda r: (r / "src/fnopt/cloth/stretch_kernel.hpp").unlink(), "`stretch_kernel` names no file"),
        "a stale folder": (lambda r: ((r / "src/fnopt/cloth/web/page.js").unlink(), (r / "src/fnopt/cloth/web").rmdir()),
                           "`web/` is no folder"),
        "a module without a row": (lambda r: ((r / "src/fnopt/contact").mkdir(), (r / "src/fnopt/contact/ccd.hpp")
                                              .write_text("\n")), "src/fnopt/contact/ has no row"),
        "a row without a folder": (lambda r: (r / "docs/design.md").write_text(
            table.replace("## 2.", "| `io/` | files (`csv`) |\n\n## 2.")), "row `io/` is no folder"),
    }
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        clean_root = pathlib.Path(tmp) / "clean"
        clean_root.mkdir()
        tree(clean_root)
        clean = problems(clean_root)
        if clean:
            failures.append(f"the clean tree: {clean}")
        for n, (name, (plant, expected)) in enumerate(plants.items()):
            root = pathlib.Path(tmp) / f"plant{n}"
            root.mkdir()
            tree(root)
            plant(root)
            found = problems(root)
            if len(found) != 1 or expected not in found[0]:
                failures.append(f"{name}: {found}")
    print("check-layout-table self-test: " + ("passed" if not failures else "FAILED " + "; ".join(failures)))
    return 1 if failures else 0


def main() -> int:
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent
    found = problems(root)
    for line in found:
        print("check-layout-table: " + line)
    if not found:
        print("check-layout-table: design.md §1's table names every folder and file of src/fnopt, app/ and python/")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
