"""The Python bindings (python/climbsim_module.cc), run from ctest as python_tests."""
import copy
import csv
import json
import os

import numpy as np
import pytest

import climbsim

SOURCE = os.environ.get("CLIMBSIM_SOURCE_DIR",
                        os.path.join(os.path.dirname(__file__), "..", ".."))

# The gecko on the wall with pads and a CPG (no reflexes: their releases bypass the command).
WALL = {
    "robot": "gecko",
    "scene": "wall",
    "duration_s": 1.0,
    "adhesion": {"start_attached": True},
    "cpg": {"gait": "trot", "frequency_hz": 1.0, "control_period_s": 0.01},
    "outputs": {"trajectory_rate_hz": 100},
    "fall": {"stop": False},  # the trot without reflexes falls; the run goes on through it
}


def test_scenario_from_dict_runs():
    s = climbsim.scenario_from_dict({"robot": "gecko", "scene": "floor", "duration_s": 0.5,
                                     "cpg": {"gait": "trot"}})
    sim = climbsim.Simulation(s)
    summary = sim.run()
    assert summary["steps"] == 500
    assert summary["stable"] is True
    assert summary["effects"] == ["cpg", "trajectory"]
    assert "robot: gecko" in s.to_yaml()


def test_bad_key_raises_input_error_with_the_key():
    with pytest.raises(climbsim.InputError, match="cpg.frequncy_hz"):
        climbsim.scenario_from_dict({"robot": "gecko", "scene": "floor", "duration_s": 1,
                                     "cpg": {"frequncy_hz": 1.0}})


def test_numpy_trajectory_and_events_equal_the_run_folder(tmp_path):
    sim = climbsim.Simulation(climbsim.scenario_from_dict(WALL))
    sim.run()
    run = tmp_path / "run"
    sim.write(str(run))
    traj = sim.trajectory()
    with open(run / "trajectory.csv") as f:
        rows = list(csv.reader(f))
    assert list(traj.keys()) == rows[0]
    table = np.array([[float(v) for v in r] for r in rows[1:]])
    assert table.shape == (101, len(rows[0]))
    for i, name in enumerate(rows[0]):
        assert np.array_equal(traj[name], table[:, i]), name  # bit for bit

    ev = sim.events()
    with open(run / "events.csv") as f:
        erows = list(csv.DictReader(f))
    assert len(erows) == len(ev["time_s"]) > 0
    assert [r["event"] for r in erows] == list(ev["event"])
    assert [r["pad"] for r in erows] == list(ev["pad_name"])
    summary = json.loads((run / "summary.json").read_text())
    assert summary["distance_m"] == sim.summary()["distance_m"]


class Recorder(climbsim.Controller):
    """Appended after the built-in CPG: records its commands and the start pose."""

    def __init__(self):
        super().__init__()
        self.targets, self.steps = [], []

    def initial_pose(self, pose):
        self.start_q = pose.joint_angle_rad.copy()
        self.start_base = pose.base_pos_m.copy()

    def update(self, obs, cmd):
        self.steps.append(obs.step)
        self.targets.append(cmd.target_rad.copy())


class Replay(climbsim.Controller):
    """Drives the servos alone with the recorded commands."""

    def __init__(self, rec, period_s):
        super().__init__()
        self.rec, self.period_s, self.tick = rec, period_s, 0

    def control_period_s(self):
        return self.period_s

    def initial_pose(self, pose):
        pose.joint_angle_rad[:] = self.rec.start_q
        pose.base_pos_m[:] = self.rec.start_base

    def reset(self):
        self.tick = 0

    def update(self, obs, cmd):
        assert obs.step == self.rec.steps[self.tick]
        cmd.target_rad[:] = self.rec.targets[self.tick]
        self.tick += 1


def test_python_replay_of_the_builtin_commands_is_bit_for_bit():
    rec = Recorder()
    original = climbsim.Simulation(climbsim.scenario_from_dict(WALL), controller=rec)
    a = original.run()
    assert a["effects"][1] == "cpg+python" or a["effects"][1].startswith("cpg+")
    assert len(rec.targets) == 100

    bare = copy.deepcopy(WALL)
    del bare["cpg"]
    replayed = climbsim.Simulation(climbsim.scenario_from_dict(bare),
                                   controller=Replay(rec, 0.01))
    b = replayed.run()
    ta, tb = original.trajectory(), replayed.trajectory()
    assert ta.keys() == tb.keys()
    for name in ta:
        assert np.array_equal(ta[name], tb[name]), name
    assert a["distance_m"] == b["distance_m"]
    ea, eb = original.events(), replayed.events()
    assert np.array_equal(ea["time_s"], eb["time_s"])
    assert list(ea["event"]) == list(eb["event"])


def test_observation_and_offsets_on_top_of_the_cpg():
    seen = {}

    class Lift(climbsim.Controller):
        def update(self, obs, cmd):
            seen["legs"] = obs.legs
            seen["q"] = obs.joint_angle_rad.copy()
            seen["phase"] = obs.cpg_phase_rad.copy()
            seen["attached"] = obs.attached.copy()
            cmd.offset_rad[:] = 0.02

    sim = climbsim.Simulation(climbsim.scenario_from_dict(WALL), controller=Lift())
    for _ in range(25):
        assert sim.step()
    c = sim.command()
    assert np.all(c["offset_rad"] == 0.02)
    assert seen["legs"] == 4 and seen["q"].shape == (12,) and seen["phase"].shape == (4,)
    assert seen["attached"].dtype == bool


def test_pulloff_straight_pull_is_the_pad_capacity():
    r = climbsim.pulloff(0.0, model="bonds")
    assert r["detached"]
    # A central normal pull on a uniform grid breaks every bond at once: F = σ_T·A.
    assert r["force_n"] == pytest.approx(r["capacity_n"], rel=0.02)


def test_optimise_returns_its_best_evaluation(tmp_path):
    scenario = tmp_path / "opt.yaml"
    scenario.write_text(
        "robot: gecko\nscene: floor\nduration_s: 1\n"
        "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.35, 0.0, 0.0]\n"
        "  lift_rad: [0.0, 0.4, 0.3]\noutputs:\n  trajectory_rate_hz: 0\n"
        "optimise:\n  parameters:\n"
        "    - {key: cpg.frequency_hz, start: 1.0, min: 0.5, max: 2.5}\n"
        "  algorithm: chain\n  max_evaluations: 4\n  starts: 1\n")
    r = climbsim.optimise(str(scenario), str(tmp_path / "out"), threads=1)
    assert r["evaluations"] == 4
    # J is minimised (docs/optimise.md); the first evaluation is the scenario as given.
    assert r["best_objective"] <= r["start_objective"]
    assert r["best_objective"] == min(r["history_objective"])
    assert (tmp_path / "out" / "best.yaml").exists()
