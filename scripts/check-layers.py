#!/usr/bin/env python3
"""Checks docs/design.md §1's layer order: a module of src/fnopt includes only its own layer and
the layers before it. The order is read from the line of design.md §1 that starts with
"layers:", so the documentation and the check cannot drift apart.

    scripts/check-layers.py [ROOT]     check the tree at ROOT (default: this repository)
    scripts/check-layers.py --self-test   check that a planted violation is caught

Exit status 0 when every include respects the order; 1 with one line per violation.
"""
import pathlib
import re
import sys
import tempfile

INCLUDE = re.compile(r'^\s*#\s*include\s*<fnopt/([a-z_]+)/', re.MULTILINE)


def layer_order(design: pathlib.Path) -> list:
    for line in design.read_text(encoding="utf-8").splitlines():
        line = line.strip()
        if line.startswith("layers:"):
            return [name.strip() for name in line[len("layers:"):].split("→")]
    raise SystemExit(f"check-layers: {design}: no line starting with 'layers:' in §1")


def violations(root: pathlib.Path) -> list:
    order = layer_order(root / "docs" / "design.md")
    rank = {name: i for i, name in enumerate(order)}
    found = []
    src = root / "src" / "fnopt"
    for module in sorted(p for p in src.iterdir() if p.is_dir()):
        if module.name not in rank:
            found.append(f"src/fnopt/{module.name}: a module missing from design.md §1's layers")
            continue
        for path in sorted(module.rglob("*.[ch]pp")):
            for included in INCLUDE.findall(path.read_text(encoding="utf-8")):
                if included not in rank:
                    found.append(f"{path.relative_to(root)}: includes <fnopt/{included}/...>, not a layer")
                elif rank[included] > rank[module.name]:
                    found.append(f"{path.relative_to(root)}: includes <fnopt/{included}/...>, "
                                 f"a layer above {module.name}")
    return found


def self_test() -> int:
    """A tree whose cloth includes simulation must fail; the same tree without it must pass."""
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        (root / "docs").mkdir()
        (root / "docs" / "design.md").write_text("## 1. Layout\n\n    layers: util → cloth → simulation\n")
        for module, text in (("util", ""), ("cloth", "#include <fnopt/util/types.hpp>\n"),
                             ("simulation", "#include <fnopt/cloth/grid.hpp>\n")):
            (root / "src" / "fnopt" / module).mkdir(parents=True)
            (root / "src" / "fnopt" / module / "a.hpp").write_text(text)
        clean = violations(root)
        (root / "src" / "fnopt" / "cloth" / "b.cpp").write_text("#include <fnopt/simulation/rollout.hpp>\n")
        planted = violations(root)
        (root / "src" / "fnopt" / "extra").mkdir()
        missing = violations(root)
    ok = not clean and len(planted) == 1 and "a layer above cloth" in planted[0] and \
        any("missing from" in v for v in missing)
    print("check-layers self-test: " + ("passed" if ok else f"FAILED {clean} {planted} {missing}"))
    return 0 if ok else 1


def main() -> int:
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent
    found = violations(root)
    for line in found:
        print("check-layers: " + line)
    if not found:
        print("check-layers: every include of src/fnopt respects design.md §1's layers")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
