#!/usr/bin/env python3
"""What a controller written in Python costs per physics step against the same one in C++.

Both run the same law (climbsim.SineOffsetController: an offset a·sin(2πft) on every
hip_pitch) at every physics step on the gecko on the wall (pads, CPG underneath), in one
process, alternately, best of --repeat; the ratio is what docs/python.md reports.

    PYTHONPATH=build/python python3 python/benchmarks/controller_cost.py [--duration 2] [--repeat 3]
"""
import argparse
import math
import time

import climbsim

WALL = {"robot": "gecko", "scene": "wall", "adhesion": {"start_attached": True},
        "cpg": {"gait": "trot", "control_period_s": 0.001}, "outputs": {"trajectory_rate_hz": 0}}


class PySine(climbsim.Controller):
    def __init__(self, a, f):
        super().__init__()
        self.a, self.f = a, f

    def update(self, obs, cmd):
        cmd.offset_rad[1::3] = self.a * math.sin(2 * math.pi * self.f * obs.time_s)


def timed(duration, controller):
    d = dict(WALL, duration_s=duration)
    sim = climbsim.Simulation(climbsim.scenario_from_dict(d), controller=controller)
    t0 = time.perf_counter()
    s = sim.run()
    wall = time.perf_counter() - t0
    return wall / s["steps"], s


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--duration", type=float, default=2.0)
    p.add_argument("--repeat", type=int, default=3)
    args = p.parse_args()
    best = {"cpp": math.inf, "python": math.inf}
    for _ in range(args.repeat):
        cpp, sc = timed(args.duration, climbsim.SineOffsetController(0.05, 1.0))
        py, sp = timed(args.duration, PySine(0.05, 1.0))
        assert sc["distance_m"] == sp["distance_m"], "the two controllers must do the same"
        best["cpp"] = min(best["cpp"], cpp)
        best["python"] = min(best["python"], py)
    for k, v in best.items():
        print(f"{k:7s} {v * 1e6:8.2f} us/step")
    print(f"python/cpp step time ratio {best['python'] / best['cpp']:.2f}; "
          f"a Python controller call costs {(best['python'] - best['cpp']) * 1e6:.2f} us more "
          f"than the C++ one")


if __name__ == "__main__":
    main()
