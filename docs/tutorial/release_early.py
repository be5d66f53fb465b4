#!/usr/bin/env python3
"""A controller of one's own, in Python: let a pad go before its bonds tear.

    python3 docs/tutorial/release_early.py [threshold]

On top of the built-in CPG and reflexes, each step: a pad whose utilisation (peak bond demand
over strength; a bond breaks at 1) passes the threshold is released. Runs the gecko on the wall
for 10 s without and with it and prints the distance and each pad's peel peak, which the
release caps (summary.json's adhesion.pads.<pad>.utilisation_peel_peak).
"""
import sys

import climbsim


class ReleaseEarly(climbsim.Controller):
    def __init__(self, threshold):
        super().__init__()
        self.threshold = threshold

    def update(self, obs, cmd):
        for leg, pad in enumerate(obs.pads):
            if pad.attached and pad.utilisation > self.threshold:
                cmd.release[leg] = 1


threshold = float(sys.argv[1]) if len(sys.argv) > 1 else 0.95
for name, controller in (("cpg+reflexes", None), (f"release at {threshold}", ReleaseEarly(threshold))):
    scenario = climbsim.load_scenario("examples/gecko_wall.yaml")
    scenario.duration_s = 10
    sim = climbsim.Simulation(scenario) if controller is None else \
        climbsim.Simulation(scenario, controller=controller)
    r = sim.run()
    pads = r["adhesion"]["pads"]  # LF_pad LH_pad RF_pad RH_pad, sorted
    peel = " ".join(f"{pads[p]['utilisation_peel_peak']:.3f}" for p in sorted(pads))
    stance = " ".join(f"{pads[p]['utilisation_stance_peak']:.3f}" for p in sorted(pads))
    print(f"{name:18s} distance_m {r['distance_m']:.4f}  fell {r['fell']}  "
          f"peel peak {peel}  stance peak {stance}")
