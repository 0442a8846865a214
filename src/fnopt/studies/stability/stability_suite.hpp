#pragma once
// The stability study (docs/design.md §8 "Stability"; `fnopt stability`): a fixed suite of
// stiff and extreme cases, each a change of a base scene (the default: 32^2, corner handles,
// xy_v2, the default material, dt = 1/60), every inner optimizer on every case, one row per
// case x optimizer. Optimizers come from a factory: the study (studies/stability/stability_study.hpp) makes
// them by name through the registry, tests inject their own.
//
// Per row: finished / diverged (the step, and RolloutResult::divergence) / error (an exception:
// the suite goes on), max edge strain, energy growth, e_3D against the case's Newton reference,
// ms/frame, iterations per frame, and the steps that stopped for a reason other than convergence
// (for Newton, which must never fail silently, every step short of its tolerance).
//
// Energy growth: with E(t) the total energy (kinetic + potential, StepRecord::energy) and E_0 the
// energy of the initial rest state, and E_min the lowest energy of the Newton reference (E_0
// included),
//     growth = (max_t E(t) - E_min) / (max_t E_ref(t) - E_min)      (maxima include E_0)
// i.e. the run's energy peak over the reference's, both measured from the reference's floor
// (gravity makes E negative, so a plain ratio of peaks means nothing). 1 for the reference
// itself and ~1 for a healthy run; >> 1 for a blow-up (a diverging step's elastic energy
// counts); < 1 for a run that loses energy (under-solved steps dissipate).
#include <fnopt/studies/stability/stability_cases.hpp>
#include <fnopt/studies/stability/stability_run.hpp>
#include <fnopt/studies/stability/stability_summary.hpp>
#include <fnopt/studies/stability/stability_table.hpp>
