"""Contact with obstacles: every method on the contact scenes of examples/scenes (fnopt compare --scene), e_CD
against Newton per scene and grid, the smallest obstacle and cloth-cloth distances and the intersection counts;
then far obstacles' cost (fnopt bench contact)."""

import os
import re

from . import REPOSITORY
from .assemble import section
from .compare import budget_flags, compare_rows
from .files import write_csv
from .runner import PartFailed
from .tables import fmt, fnum, markdown_table

SCENES = os.path.join(REPOSITORY, "examples", "scenes")
# A row of fnopt bench contact's table: grid, method, case, ms/frame without and with it, ratio, same rollout.
BENCH_CONTACT_ROW = re.compile(r"^\s*(\d+)\^2\s+(\S+)\s+(\S+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+(\S+)\s*$")
BENCH_HEADER = ["grid", "method", "case", "ms/frame without", "with", "ratio", "same rollout"]


def scene_cells(grids, scenes, results, text_of):
    """{(method, N): ["32² / 64² / ..." per scene]}, each grid's cell text_of(its compare.csv row), "—" for none;
    the keys in the order the rows first give them."""
    cells = {}
    for name, _ in scenes:
        for r in results[name]:
            cells.setdefault((r["method"], r["N"]), {}).setdefault(name, {})[r["resolution"]] = text_of(r)
    return {key: [" / ".join(by_scene.get(name, {}).get(g, "—") for g in grids) for name, _ in scenes]
            for key, by_scene in cells.items()}


def contact_table(grids, scenes, results):
    """A row per (method, N) over the scenes' compare.csv rows (results: {scene: rows}): e_CD per scene as
    "32² / 64² / ..." ("diverged" where it did), the smallest obstacle and cloth-cloth distances in mm, the self-
    and mesh intersections summed over every run, runs diverged."""
    cells = scene_cells(grids, scenes, results,
                        lambda r: fmt(fnum(r["e_cd_x1e3"])) if r["diverged"] == "no" else "diverged")
    smallest, diverged, crossings = {}, {}, {}
    for name, _ in scenes:
        for r in results[name]:
            key = (r["method"], r["N"])
            done = r["diverged"] == "no"
            for column in ("min_obstacle_distance_m", "min_cloth_distance_m"):
                distance = fnum(r.get(column))
                if distance is not None:
                    smallest.setdefault(key, {})[column] = min(smallest.get(key, {}).get(column, distance), distance)
            for column in ("self_intersections", "mesh_intersections"):
                count = fnum(r.get(column))
                if count is not None:
                    crossings.setdefault(key, {})[column] = crossings.get(key, {}).get(column, 0) + int(count)
            diverged.setdefault(key, [0, 0])
            diverged[key][0] += not done
            diverged[key][1] += 1
    table = []
    for key in cells:
        row = [key[0], key[1] or "converged"] + cells[key]
        for column in ("min_obstacle_distance_m", "min_cloth_distance_m"):
            value = smallest.get(key, {}).get(column)
            row.append(fmt(1e3 * value) if value is not None else "—")
        for column in ("self_intersections", "mesh_intersections"):
            value = crossings.get(key, {}).get(column)
            row.append(str(value) if value is not None else "—")
        row.append("%d/%d" % tuple(diverged[key]))
        table.append(row)
    return table


def contact_cost_table(grids, scenes, results):
    """A row per (method, N): its CPU ms/frame per scene as "32² / 64² / ...", the time side of the e_CD table."""
    cells = scene_cells(grids, scenes, results, lambda r: fmt(fnum(r["ms_per_frame_cpu"]), 3))
    return [[key[0], key[1] or "converged"] + row for key, row in cells.items()]


def far_obstacles_cost(ctx, part, plan_):
    """fnopt bench contact: (its command, its table's rows, the CSV written)."""
    args = ["bench", "contact"] + plan_["bench"] + ["--threads", "1"]
    text = ctx.run(part + " bench", args)
    rows = [m.groups() for m in (BENCH_CONTACT_ROW.match(l) for l in text.splitlines()) if m]
    if not rows:
        raise PartFailed("%s: no table in bench contact's output" % part)
    table = [[g + "²"] + list(rest) for g, *rest in rows]
    path = os.path.join(ctx.out, part, "bench-contact.csv")
    write_csv(path, BENCH_HEADER, table)
    return args, table, path


def part_contact(ctx, part, plan_):
    """Every method on the example contact scenes at each grid: e_CD against Newton per scene and grid, and the
    smallest vertex-obstacle distance of any run; then far obstacles' cost."""
    grids = plan_["res"].split(",")
    header = ["method", "N"] + ["%s e_CD × 10³ (%s)" % (name, " / ".join(g + "²" for g in grids))
                                for name, _ in plan_["scenes"]] + [
        "smallest obstacle distance (mm)", "smallest cloth-cloth distance (mm)", "self-intersections",
        "mesh intersections", "diverged"]
    runs, commands = [], []
    for name, frames in plan_["scenes"]:
        scene = os.path.join(SCENES, name + ".scene")
        args = (["compare", "--scene", scene, "--res", plan_["res"], "--frames", str(frames), "--motions", "static"] +
                budget_flags(plan_["budgets"]) + ["--threads", "1"] + ctx.plan["compare_extra"] +
                ctx.out_flags(os.path.join(ctx.out, part, name)))
        commands.append(ctx.shown(args).replace(SCENES + os.sep, "examples/scenes/"))
        runs.append((part + " " + name, args))
    ctx.run_all(runs)
    results = {name: compare_rows(os.path.join(ctx.out, part, name)) for name, _ in plan_["scenes"]}
    table = contact_table(grids, plan_["scenes"], results)
    path = os.path.join(ctx.out, part, "contact.csv")
    write_csv(path, header, table)
    cost_header = ["method", "N"] + ["%s ms/frame (%s)" % (name, " / ".join(g + "²" for g in grids))
                                     for name, _ in plan_["scenes"]]
    cost_table = contact_cost_table(grids, plan_["scenes"], results)
    cost_path = os.path.join(ctx.out, part, "contact-cost.csv")
    write_csv(cost_path, cost_header, cost_table)
    bench_args, bench_table, bench_path = far_obstacles_cost(ctx, part, plan_)
    body = ("The scenes of `examples/scenes/` (a released cloth on a sphere above a floor, on a table top with an "
            "overhang, on a plane tilted by 30° with friction 0.4; a sphere pushed through the hanging cloth; a cloth "
            "hung over a thin rod; a cloth dropped and pushed so that it folds; the sphere and table as meshes; a "
            "drape over a mannequin mesh; an animated paddle through the hanging cloth), every method against "
            "Newton converging on every step. Over every frame, scene and grid: the smallest distance of the cloth "
            "to an obstacle and of the cloth to itself (vertex-disjoint primitives; ≥ the contact thickness, 1 mm: no "
            "penetration), and the exact self- and mesh intersections of the stored frames summed over the runs "
            "(`fnopt evaluate`'s counts; 0: nothing crossed).\n\n" +
            markdown_table(header, table) + "\n\nThe same runs' cost, CPU ms/frame (each scene's `compare.svg` in the "
            "output directory plots e_CD against it):\n\n" + markdown_table(cost_header, cost_table) +
            "\n\nContact's cost, alternated runs, medians: far-obstacles, the benchmark "
            "scene with and without a floor and a sphere far from the cloth; far-mesh, the same sphere as a mesh; "
            "self-contact, the sphere drape without and with self-contact.\n\n```\n" +
            ctx.shown(bench_args) + "\n```\n\n" + markdown_table(BENCH_HEADER, bench_table))
    return section("Contact with obstacles", commands, body), [path, cost_path, bench_path]
