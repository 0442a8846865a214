"""The plans: what each part runs, in full and in --quick. A method, budget, grid or scene that the release's
tables should show is added here; the parts turn these plans into fnopt commands."""

EVAL = "eval"  # compare's name for the fifteen evaluation motions
OFF_CORNER_PRESETS = ["diagonal", "mid-edge", "corner-center", "single-mid-edge", "single-center"]
# The contact part's scenes (examples/scenes/NAME.scene) and the frames each runs.
CONTACT_SCENES = [("drape", 120), ("table", 120), ("pushed-sphere", 150), ("tilted-plane", 120), ("rod-hang", 150),
                  ("fold-push", 150), ("drape-mesh", 120), ("table-mesh", 120), ("mannequin", 150), ("paddle", 150)]


def frontier_runs(quick):
    """(grid, motions, frames, {method: budgets}) of each frontier part."""
    if quick:
        budgets = {"fnopt": [2], "pqn": [2, 5], "newton": [2]}
        return [(12, "xy_v2,rot_h0", 3, budgets), (16, "xy_v2,rot_h0", 3, budgets)]
    budgets = {
        "fnopt": [10, 20],
        "fnopt-ss": [10, 20],
        "pqn": [5, 10, 20, 40],
        "implicit-euler": [],
        "newton": [2, 3, 5],
        "lbfgs": [120],
        "lbfgs-ls": [120],
    }
    three = "xy_v2,rot_h0,xyz_v3"
    return [(32, EVAL, 390, budgets), (64, three, 390, budgets), (100, three, 390, budgets)]


def plan(args):
    """Every part's plan as a dict by part (the command line's --quick and --repeat decide it), with the rough
    seconds each part takes for the ETA and the flags every compare run of a part gets."""
    quick = args.quick
    p = {"quick": quick}
    p["frontier"] = frontier_runs(quick)
    p["bench"] = {"res": "12,16" if quick else "32,64,100", "frames": 3 if quick else 390,
                  "repeat": 2 if quick else args.repeat}
    p["speed"] = {"res": "8" if quick else "32,64,100", "frames": 3 if quick else 390}
    # The preset's own grids and methods, with 200^2 added; --quick: one grid finer than 32.
    p["superres"] = ({"res": "40", "frames": 2, "step_samples": 1} if quick else
                     {"res": "32x64,64x32,48,48x80,64,100,128,200", "frames": None, "step_samples": None})
    p["offcorner"] = ([(12, ["diagonal", "mid-edge"], 3, 2)] if quick else
                      [(32, OFF_CORNER_PRESETS, 150, 10), (64, OFF_CORNER_PRESETS, 150, 10)])
    p["offcorner_methods"] = ["pqn", "fnopt"] if quick else ["pqn", "fnopt", "fnopt-ss"]
    # ARCSim has every 32^2 motion, and xy_v2, xyz_v3, rot_h0 at 64^2, xy_v2 at 100^2.
    p["arcsim"] = ([(32, "xy_v2", 4, {"pqn": [2], "fnopt": [2]})] if quick else
                   [(32, EVAL, 390, {"fnopt": [5, 10, 20], "fnopt-ss": [5, 10, 20], "pqn": [10], "newton": []}),
                    (64, "xy_v2,rot_h0,xyz_v3", 390,
                     {"fnopt": [5, 10, 20], "fnopt-ss": [5, 10, 20], "pqn": [10], "newton": []}),
                    (100, "xy_v2", 390, {"fnopt": [5, 10, 20], "fnopt-ss": [5, 10, 20], "pqn": [10],
                                         "lbfgs": [120], "newton": []})])
    p["stability"] = ({"cases": "baseline,stretch-x100", "frames": 3, "optimizers": "pqn,fnopt"} if quick else
                      {"cases": "all", "frames": None,
                       "optimizers": "newton,pqn,fnopt,fnopt-ss,implicit-euler,lbfgs,lbfgs-ls"})
    p["contact"] = ({"res": "12", "scenes": [(name, 4) for name, _ in CONTACT_SCENES],
                     "budgets": {"newton": [], "pqn": [2]}, "bench": ["--res", "12", "--frames", "3"]} if quick else
                    {"res": "32,64,100", "scenes": CONTACT_SCENES,
                     "budgets": {"newton": [], "pqn": [10], "fnopt": [10], "fnopt-ss": [10], "implicit-euler": [],
                                 "lbfgs": [100], "lbfgs-ls": [100], "adam": [500], "gd": [500]},
                     "bench": ["--res", "32,64,100", "--frames", "60", "--repeat", "4"]})
    p["adjoint"] = ({"gradcheck": ["--res", "6", "--frames", "8"], "contact_gradcheck": ["--res", "6", "--frames", "8"],
                     "buckling_gradcheck": ["--res", "8", "--frames", "8"], "hidden_fit": (8, 10),
                     "bench": ["--res", "8", "--frames", "3"],
                     "fit_handles": ["--res", "6", "--frames", "12", "--passes", "8"], "passes": [2, 4, 8],
                     "buckling_fit": ["--res", "6", "--frames", "12", "--speed", "4", "--passes", "12",
                                      "--smoothing", "0.003", "--samples", "2"],
                     "fit_material": None} if quick else
                    {"gradcheck": [], "contact_gradcheck": ["--res", "8", "--frames", "30"],
                     "buckling_gradcheck": ["--res", "12"], "hidden_fit": (32, 60),
                     "bench": ["--res", "32,64,100", "--frames", "390"],
                     "fit_handles": ["--passes", "100"], "passes": [10, 20, 40, 60, 100],
                     "buckling_fit": ["--res", "32", "--frames", "40", "--speed", "4", "--passes", "120",
                                      "--smoothing", "0.003", "--samples", "4"],
                     "fit_material": ["--frames", "210", "--cd-samples", "4000", "--cd-stride", "4"]})
    # Rough seconds per part on one idle core, for the ETA only (scaled by how the finished parts went).
    p["estimate_s"] = ({"frontier-12": 15, "frontier-16": 20, "newton-cost": 3, "speed": 5, "superres": 20,
                        "offcorner-12": 20,
                        "arcsim": 10, "stability": 10, "contact": 10, "adjoint": 10, "paper": 0} if quick else
                       {"frontier-32": 9000, "frontier-64": 14400, "frontier-100": 36000,
                        "newton-cost": 1500 * args.repeat, "speed": 1500, "superres": 10800, "offcorner-32": 3600,
                        "offcorner-64": 24000, "arcsim": 12000, "stability": 3600, "contact": 43200,
                        "adjoint": 7200, "paper": 0})
    # Fewer samples where the grids are tiny: the per-step error's reference states, e_CD's points.
    p["compare_extra"] = ["--step-samples", "2", "--cd-samples", "2000"] if quick else []
    return p
