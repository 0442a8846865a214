"""Run with the installed package's PYTHONPATH: prints where fnopt was imported from and where
its model is, then runs the shipped learned optimizer for two steps."""
import fnopt

print(fnopt.__file__)
print(fnopt.shipped_model_path())
fnopt.Simulator(fnopt.Scene(res=8, frames=2), optimizer="fnopt-ss").rollout(2)
