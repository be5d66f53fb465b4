#!/usr/bin/env python3
"""The gecko climbs the wall; plot each leg's bonded pad fraction against time.

    python3 examples/python/gecko_wall_bonded.py [--duration 10] [--out gecko_wall_bonded.png]
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

import climbsim  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--scenario", default=os.path.join(here, "..", "gecko_wall.yaml"))
parser.add_argument("--duration", type=float, default=10.0, help="simulated seconds")
parser.add_argument("--out", default="gecko_wall_bonded.png")
args = parser.parse_args()

scenario = climbsim.load_scenario(args.scenario)
scenario.duration_s = args.duration
sim = climbsim.Simulation(scenario)
summary = sim.run()
traj = sim.trajectory()  # column name -> numpy array, as in trajectory.csv

legs = [name[: -len("_pad_bonded_fraction")] for name in traj if name.endswith("_pad_bonded_fraction")]
fig, axes = plt.subplots(len(legs), 1, sharex=True, figsize=(8, 1.6 * len(legs)))
for ax, leg in zip(axes, legs):
    ax.fill_between(traj["time_s"], traj[f"{leg}_pad_bonded_fraction"], step="post")
    ax.set_ylim(0, 1.05)
    ax.set_ylabel(leg)
axes[0].set_title(f"gecko on the wall: bonded pad fraction per leg "
                  f"({summary['distance_m']:.3f} m in {summary['duration_s']:.1f} s)")
axes[-1].set_xlabel("time (s)")
fig.tight_layout()
fig.savefig(args.out, dpi=120)
print(f"distance_m {summary['distance_m']:.4f}  fell {summary['fell']}  plot {args.out}")
