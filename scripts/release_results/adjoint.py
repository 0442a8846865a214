"""Gradients through rollouts: the adjoint against central differences (fnopt gradcheck, plain and with an
obstacle), its cost (fnopt bench adjoint), and the inverse problems fnopt answers by it: handle paths to a
target (fnopt fit-handles), hidden materials fitted by gradient and by compass (fnopt fit-material) and, with
--arcsim-dir, design.md §7's material fit against ARCSim. Each step below returns (its commands, its text, the
files it wrote)."""

import os
import re

from .assemble import publish_picture, section
from .files import read_csv, write_atomic, write_csv
from .runner import PartFailed
from .tables import bench_table, fmt, fnum, markdown_table

# design.md §7's fit: the start the fit-material comparison begins from (stretch, shear, damping far off).
FIT_START = "stretch = 300\nshear = 3\nbend = 2e-5\ndensity = 0.187\ndamping = 1\n"
GRADCHECK_OBSTACLE = "sphere center=0.5,0.12,-0.6 radius=0.1 friction=0.3"
GRADCHECK_ROW = re.compile(r"^(\S+)\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$")
# Hidden materials for the fit-material comparison: (name, simulate's material flags); the second has a bend a
# tenth of the default's and a lighter cloth.
HIDDEN_MATERIALS = (("stiff", ["--stretch", "700", "--shear", "20", "--bend", "6e-5", "--damping", "2.5",
                               "--density", "0.25"]),
                    ("soft bend", ["--stretch", "300", "--shear", "45", "--bend", "2e-6", "--damping", "6",
                                   "--density", "0.15"]))
HIDDEN_HEADER = ["material", "method", "stretch/ρ error", "shear/ρ error", "bend/ρ error", "damping error",
                 "rollouts", "stop"]
BENCH_HEADER = ["grid", "forward ms/frame", "backward ms/frame", "backward / forward", "factorisations / step",
                "solves / step", "record MB", "peak RSS MB", "saddle steps", "status"]
FIT_MATERIAL_HEADER = ["method", "fitted material", "e_CD and rollouts"]
# fit-material's methods, each with its step flags (the same first step for both).
FIT_MATERIAL_METHODS = (("gradient", ["--initial-step", "0.7"]),
                        ("compass", ["--initial-step", "0.7", "--final-step", "0.08"]))


def gradcheck(ctx, part, label, extra):
    """fnopt gradcheck with extra flags, logged as PART LABEL: (its command, {parameter kind: (relative error,
    valid below)}, its unreliable: and backward pass: lines)."""
    args = ["gradcheck"] + extra + ["--threads", "1"]
    lines = ctx.run(part + " " + label, args).splitlines()
    rows = [m.groups() for m in (GRADCHECK_ROW.match(l) for l in lines) if m and m.group(1) != "parameter"]
    if not rows:
        raise PartFailed("%s: no rows in gradcheck's output" % part)
    said = [l for l in lines if l.startswith(("unreliable:", "backward pass:"))]
    return ctx.shown(args), {r[0]: (r[4], r[5]) for r in rows}, said


def gradchecks(ctx, part, d, plan_):
    """The adjoint against central differences, plain, with a sphere behind the cloth, and on a buckling cloth
    (the verdict and the unreliable kinds)."""
    plain_command, plain, plain_said = gradcheck(ctx, part, "gradcheck", plan_["gradcheck"])
    contact_command, contact, _ = gradcheck(ctx, part, "gradcheck contact",
                                            plan_["contact_gradcheck"] + ["--obstacle", GRADCHECK_OBSTACLE])
    buckling_command, buckling, buckling_said = gradcheck(ctx, part, "gradcheck buckling", plan_["buckling_gradcheck"])
    header = ["parameter", "relative error, plain scene", "valid below", "with a sphere behind the cloth (friction 0.3)",
              "buckling scene", "valid below"]
    table = [[k, plain[k][0], plain[k][1], contact.get(k, ("—",))[0], buckling.get(k, ("—", "—"))[0],
              buckling.get(k, ("—", "—"))[1]] for k in plain]
    path = os.path.join(d, "gradcheck.csv")
    write_csv(path, header, table)
    text = ("The adjoint against central differences of the rollout, a row per parameter kind, and the backward "
            "pass's verdict, the perturbation below which each kind's gradient holds (relative for the material, "
            "the parameter's unit along a unit direction for a vector):\n\n" + markdown_table(header, table) +
            "\n\nThe plain scene's and the buckling scene's verdicts and unreliable kinds, as gradcheck prints them:"
            "\n\n```\n" + "\n".join(plain_said + buckling_said) + "\n```\n\n")
    return [plain_command, contact_command, buckling_command], text, [path]


def backward_cost(ctx, part, d, plan_):
    """fnopt bench adjoint: the backward pass's cost against the forward pass, and the record's memory."""
    args = ["bench", "adjoint"] + plan_["bench"] + ["--threads", "1"]
    head, rows = bench_table(ctx.run(part + " bench", args))
    if head is None or not rows:
        raise PartFailed("%s: no table in bench adjoint's output" % part)
    rows = [r[:len(BENCH_HEADER)] for r in rows]
    path = os.path.join(d, "bench-adjoint.csv")
    write_csv(path, BENCH_HEADER, rows)
    text = ("Cost of the backward pass against the recorded forward pass it differentiates (Newton to 1e-10 m/s², "
            "exact steps), and the memory the record holds:\n\n" + markdown_table(BENCH_HEADER, rows) + "\n\n")
    return [ctx.shown(args)], text, [path]


def best_loss_table(history, passes):
    """fit-handles' losses {method: [(passes, loss)]} as (header, rows): each method's start loss and its best loss
    within each number of passes."""
    header = ["method", "start loss m²"] + ["after %d passes" % n for n in passes]
    table = [[method, fmt(points[0][1])] +
             [fmt(min((loss for k, loss in points if k <= n), default=None)) for n in passes]
             for method, points in history.items()]
    return header, table


def fit_handles(ctx, part, d, plan_):
    """fnopt fit-handles: the best loss after each planned number of passes, per method, and its chart."""
    loss_csv = os.path.join(d, "fit-handles.csv")
    args = (["fit-handles"] + plan_["fit_handles"] + ["--threads", "1", "--csv", ctx.rel(loss_csv),
                                                      "--plot", ctx.rel(os.path.join(d, "fit-handles.svg"))])
    said = [l for l in ctx.run(part + " fit-handles", args).splitlines()
            if l.startswith(("scene:", "target:", "path:"))]
    history = {}
    for r in read_csv(loss_csv):
        history.setdefault(r["method"], []).append((int(r["passes"]), fnum(r["loss_m2"])))
    header, table = best_loss_table(history, plan_["passes"])
    path = os.path.join(d, "fit-handles-table.csv")
    write_csv(path, header, table)
    chart = publish_picture(ctx, os.path.join(d, "fit-handles.svg"), "fit-handles.svg",
                            "the loss against passes, gradient and compass")
    text = ("Handle paths to a target (`fnopt fit-handles`; %s): the best loss after N passes, a gradient "
            "evaluation counting two.\n\n" % "; ".join(said) + markdown_table(header, table) + chart + "\n")
    return [ctx.shown(args)], text, [path, loss_csv]


def buckling_fit(ctx, part, d, plan_):
    """fnopt fit-handles on a buckling cloth: the exact gradient and compass, then the gradient of the randomized
    smoothing of the loss, each run's best loss after N passes and its closing line."""
    flags = plan_["buckling_fit"]
    smoothing = flags.index("--smoothing")
    plain, smoothed = flags[:smoothing], flags[smoothing:]
    sigma, samples = smoothed[1], smoothed[3]
    runs = (("exact", ["--method", "both"] + plain),
            ("smoothed", ["--method", "gradient"] + plain + smoothed))
    commands, history, closing = [], {}, []
    for label, extra in runs:
        loss_csv = os.path.join(d, "fit-handles-buckling-%s.csv" % label)
        args = ["fit-handles"] + extra + ["--threads", "1", "--csv", ctx.rel(loss_csv)]
        out = ctx.run(part + " fit-handles buckling " + label, args).splitlines()
        commands.append(ctx.shown(args))
        closing += [l for l in out if l.startswith(("gradient loss", "compass  loss", "compass loss"))]
        for r in read_csv(loss_csv):
            method = r["method"] if label == "exact" else "gradient, smoothed (σ %s m, %s samples)" % (sigma, samples)
            history.setdefault(method, []).append((int(r["passes"]), fnum(r["loss_m2"])))
    passes = [n for n in (10, 20, 40, 60, 80, 100, 120) if n <= int(plain[plain.index("--passes") + 1])]
    header, table = best_loss_table(history, passes)
    path = os.path.join(d, "fit-handles-buckling.csv")
    write_csv(path, header, table)
    text = ("\nThe same fit on a buckling cloth (%s): the exact gradient holds only for tiny steps there (each "
            "fit's closing line gives its verdict), and the gradient of the loss smoothed over antithetic "
            "perturbations of the control points goes on where it stops:\n\n" % " ".join(plain) +
            markdown_table(header, table) + "\n\n```\n" + "\n".join(closing) + "\n```\n")
    return commands, text, [path]


def fitted_material(path):
    """The coefficients of a material file fit-material wrote: {name: value}."""
    values = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            m = re.match(r"^\s*(\w+)\s*=\s*(\S+)", line)
            if m:
                values[m.group(1)] = float(m.group(2))
    return values


def material_text(values):
    return ", ".join("%s %s" % (k, fmt(values[k])) for k in ("stretch", "shear", "bend", "density", "damping")
                     if k in values)


def fit_material(ctx, part, d, plan_):
    """design.md §7's fit against ARCSim's 32² xy_v2 and rot_h0 from a far start, by gradient and by compass:
    the fitted material and the final e_CD line of each."""
    start = os.path.join(d, "fit-start.txt")
    write_atomic(start, FIT_START)
    refs = [os.path.join(ctx.arcsim_dir, "arcsim_N32_%s.h5" % m) for m in ("xy_v2", "rot_h0")]
    commands, rows = [], []
    for method, extra in FIT_MATERIAL_METHODS:
        out_file = os.path.join(d, "fitted-%s.txt" % method)
        args = (["fit-material", "--method", method, "--reference"] + refs +
                ["--start", ctx.rel(start), "--fit", "stretch,shear,damping"] + plan_["fit_material"] +
                extra + ["--threads", "1", "--out", ctx.rel(out_file)])
        commands.append(ctx.shown(args).replace(ctx.arcsim_dir, "ARCSIM_DIR"))
        out = ctx.run(part + " fit-material " + method, args).splitlines()
        last = [l for l in out if "e_CD x 10^3" in l and ("fitted" in l or "against" in l)]
        rows.append([method, material_text(fitted_material(out_file)), last[-1].strip() if last else "—"])
    path = os.path.join(d, "fit-material.csv")
    write_csv(path, FIT_MATERIAL_HEADER, rows)
    text = ("\ndesign.md §7's fit (32² xy_v2 and rot_h0 against ARCSim, from stretch 300, shear 3, damping "
            "1), by gradient and by compass:\n\n" + markdown_table(FIT_MATERIAL_HEADER, rows) + "\n")
    return commands, text, [path]


def hidden_fit_row(ctx, part, d, name, truth, method, reference):
    """One fit of a hidden material: (its command, its table row)."""
    out_file = os.path.join(d, "hidden-%s-%s.txt" % (name.replace(" ", "-"), method))
    args = (["fit-material", "--method", method, "--reference", ctx.rel(reference), "--threads", "1", "--out",
             ctx.rel(out_file)])
    out = ctx.run(part + " hidden " + name + " " + method, args)
    fitted = fitted_material(out_file)
    error = lambda k: fmt(100.0 * ((fitted[k] / fitted["density"]) / (truth[k] / truth["density"]) - 1.0)) + " %"
    gradient = re.search(r"; (\d+) rollouts \((\d+) recorded forward \+ (\d+) tangent passes\)", out)
    compass = re.search(r"(\d+) rollouts per reference", out)
    rollouts = ("%s (%s forward + %s tangent)" % gradient.groups() if gradient else
                compass.group(1) if compass else "—")
    stop = re.search(r"fitted \((stationary|not stationary)", out)
    return ctx.shown(args), [name, method, error("stretch"), error("shear"), error("bend"),
                             fmt(100.0 * (fitted["damping"] / truth["damping"] - 1.0)) + " %", rollouts,
                             stop.group(1) if stop else "compass converged" if "converged" in out else "budget"]


def hidden_materials(ctx, part, d, plan_):
    """Hidden materials recovered from an fnopt rollout recorded to 1e-8 m/s² (the default scene, from the default
    material), by gradient and by compass: each ratio's error, the rollouts and the stop."""
    res, frames = plan_["hidden_fit"]
    commands, rows = [], []
    for name, flags in HIDDEN_MATERIALS:
        reference = os.path.join(d, "hidden-%s.h5" % name.replace(" ", "-"))
        args = (["simulate", "--res", str(res), "--frames", str(frames)] + flags +
                ["--optimizer", "newton", "--tolerance", "1e-8", "--threads", "1", "--out", ctx.rel(reference)])
        ctx.run(part + " hidden " + name, args)
        commands.append(ctx.shown(args))
        truth = {flags[i][2:]: float(flags[i + 1]) for i in range(0, len(flags), 2)}
        for method in ("gradient", "compass"):
            command, row = hidden_fit_row(ctx, part, d, name, truth, method, reference)
            commands.append(command)
            rows.append(row)
    path = os.path.join(d, "fit-hidden.csv")
    write_csv(path, HIDDEN_HEADER, rows)
    text = ("\nHidden materials recovered from their own %d² rollout (%d frames of xy_v2, Newton to 1e-8 m/s²), from "
            "the default material: the error of each ratio the positions determine (the density is held), the "
            "rollouts each method took and how it stopped:\n\n" % (res, frames) +
            markdown_table(HIDDEN_HEADER, rows) + "\n")
    return commands, text, [path]


def part_adjoint(ctx, part, plan_):
    """The adjoint's checks and costs, and the inverse problems fnopt answers by it: the section and its CSVs
    (the material fit only with --arcsim-dir and a plan for it)."""
    d = os.path.join(ctx.out, part)
    os.makedirs(d, exist_ok=True)
    steps = [gradchecks, backward_cost, fit_handles, buckling_fit, hidden_materials]
    if plan_["fit_material"] and ctx.arcsim_dir:
        steps.append(fit_material)
    commands, body, files = [], "", []
    for step in steps:
        step_commands, text, step_files = step(ctx, part, d, plan_)
        commands += step_commands
        body += text
        files += step_files
    return section("Gradients through rollouts", commands, body), files
