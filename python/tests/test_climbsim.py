"""The Python bindings (python/climbsim_module.cc), run from ctest as python_tests."""
import copy
import csv
import json
import os
import re
import subprocess
import sys

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


# --- The Python API is as safe and as strict as the command line ---------------------------

FLOOR = {"robot": "gecko", "scene": "floor", "duration_s": 0.05, "cpg": {"gait": "trot"}}


class Keeper(climbsim.Controller):
    """Keeps what its callbacks get, and the arrays it read or wrote, past the call."""

    def __init__(self):
        super().__init__()
        self.kept = {}

    def initial_pose(self, pose):
        self.kept.update(pose=pose, pose_q=pose.joint_angle_rad, pose_base=pose.base_pos_m)

    def update(self, obs, cmd):
        cmd.offset_rad[:] = 0.01
        self.kept.update(obs=obs, cmd=cmd, q=obs.joint_angle_rad, offset=cmd.offset_rad)


def test_callback_objects_kept_past_their_call_raise_and_their_arrays_are_copies():
    k = Keeper()
    sim = climbsim.Simulation(climbsim.scenario_from_dict(FLOOR), controller=k)
    assert sim.step()
    for name, read in [("obs", lambda o: o.joint_angle_rad), ("obs", lambda o: o.time_s),
                       ("cmd", lambda c: c.target_rad), ("pose", lambda p: p.base_pos_m)]:
        with pytest.raises(ReferenceError, match="used after the controller call"):
            read(k.kept[name])
    # The write made during the call reached the command; one made after it changes nothing.
    assert np.all(sim.command()["offset_rad"] == 0.01)
    k.kept["offset"][:] = 5.0
    k.kept["q"].setflags(write=True)  # a copy: NumPy lets its owner write it
    assert np.all(sim.command()["offset_rad"] == 0.01)
    assert all(k.kept[a].flags.owndata for a in ("q", "offset", "pose_q", "pose_base"))


def test_arrays_kept_past_the_simulation_cannot_corrupt_memory():
    # Before: these writes went into freed memory (malloc(): unaligned tcache chunk, SIGABRT).
    script = f"""
import climbsim, gc
import test_climbsim as t
k = t.Keeper()
sim = climbsim.Simulation(climbsim.scenario_from_dict(t.FLOOR), controller=k)
sim.step()
del sim
gc.collect()
for name in ("offset", "pose_q", "pose_base"):
    k.kept[name][:] = 7.0
for _ in range(3):
    climbsim.Simulation(climbsim.scenario_from_dict(t.FLOOR)).run()
try:
    k.kept["obs"].base_pos_m
except ReferenceError:
    print("ReferenceError")
"""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [os.path.dirname(__file__)] + os.environ.get("PYTHONPATH", "").split(os.pathsep)))
    r = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr  # < 0: killed by a signal
    assert r.stdout.strip() == "ReferenceError"


def steps_until_false(sim):
    """Steps taken by `while sim.step()` (the one that returned False included)."""
    for n in range(1, sim.steps_total + 10):  # bounded: a step() that never says False fails
        if not sim.step():
            return n
    pytest.fail("step() still returned True past the run's end")


def test_step_returns_false_at_the_duration_and_takes_no_step_after():
    sim = climbsim.Simulation(climbsim.scenario_from_dict(FLOOR))
    assert steps_until_false(sim) == sim.steps_total == 50
    t = sim.time_s
    assert not sim.step() and sim.time_s == t
    sim.reset()
    assert sim.step() and sim.time_s > 0


def summary_without_wall_time(s):
    return {k: v for k, v in s.items() if k not in ("wall_time_s", "realtime_factor")}


@pytest.mark.parametrize("stop", [True, False])
def test_step_driven_summary_is_run_summary(stop, tmp_path):
    scenario = copy.deepcopy(WALL)
    scenario["fall"] = {"stop": stop}
    ran = climbsim.Simulation(climbsim.scenario_from_dict(scenario)).run()
    assert ran["fell"] and ran["distance_m"] != 0
    stepped = climbsim.Simulation(climbsim.scenario_from_dict(scenario))
    n = steps_until_false(stepped)
    assert n == ran["steps"] and (n < stepped.steps_total) == stop
    assert summary_without_wall_time(stepped.summary()) == summary_without_wall_time(ran)
    stepped.write(str(tmp_path / "run"))
    written = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary_without_wall_time(written) == summary_without_wall_time(ran)
    # run() after the end takes no step and says the same.
    assert summary_without_wall_time(stepped.run()) == summary_without_wall_time(ran)


@pytest.mark.parametrize("value, shown", [(float("nan"), ".nan"), (-1.0, "-1"), (0.0, "0"),
                                          (1e300, "1e+300"), (float("inf"), ".inf")])
def test_scenario_setter_refuses_what_the_loader_refuses(value, shown):
    s = climbsim.scenario_from_dict(FLOOR)
    with pytest.raises(climbsim.InputError, match=r"duration_s: .*" + re.escape(shown)):
        s.duration_s = value
    assert s.duration_s == 0.05  # unchanged
    with pytest.raises(climbsim.InputError, match="robot: .*no bundled robot 'snail'"):
        s.robot = "snail"
    assert s.robot == "gecko"


def test_scenario_setter_sets_through_the_loader():
    s = climbsim.scenario_from_dict(FLOOR)
    before = s.to_yaml()
    s.duration_s = 0.05
    assert s.to_yaml() == before
    s.duration_s = 0.02
    assert climbsim.Simulation(s).run()["steps"] == 20


def test_scenario_from_yaml_checks_like_a_file():
    with pytest.raises(climbsim.InputError, match="second YAML document"):
        climbsim.scenario_from_yaml("robot: gecko\n---\nrobot: spider\n")
    with pytest.raises(climbsim.InputError, match="empty"):
        climbsim.scenario_from_yaml("")


class Period(climbsim.Controller):
    def __init__(self, period_s):
        super().__init__()
        self.period_s = period_s

    def control_period_s(self):
        return self.period_s

    def update(self, obs, cmd):
        pass


@pytest.mark.parametrize("period_s", [-1.0, float("nan"), 1e300, float("inf"), 0.0015])
def test_controller_period_must_be_a_whole_number_of_steps(period_s):
    bare = {k: v for k, v in FLOOR.items() if k != "cpg"}
    with pytest.raises(climbsim.InputError, match="control_period_s"):
        climbsim.Simulation(climbsim.scenario_from_dict(bare), controller=Period(period_s))
    with pytest.raises(climbsim.InputError, match="control_period_s"):
        climbsim.Simulation(climbsim.scenario_from_dict(bare),
                            controller=climbsim.SineOffsetController(0.1, 1.0, period_s))


def test_controller_period_accepts_zero_and_multiples():
    bare = {k: v for k, v in FLOOR.items() if k != "cpg"}
    for period_s, steps in [(0.0, 1), (0.002, 2), (0.01, 10)]:
        sim = climbsim.Simulation(climbsim.scenario_from_dict(bare), controller=Period(period_s))
        assert sim.control_period_steps == steps


def test_optimise_refuses_what_the_cli_refuses(tmp_path):
    out = tmp_path / "out"
    for kwargs, key in [({"max_evaluations": 0}, "max_evaluations"),
                        ({"max_evaluations": -3}, "max_evaluations"),
                        ({"threads": -1}, "threads"), ({"threads": 5000}, "threads")]:
        with pytest.raises(climbsim.InputError, match=key):
            climbsim.optimise(os.path.join(SOURCE, "examples", "gecko_wall.yaml"), str(out),
                              **kwargs)
    assert not out.exists()  # refused before anything ran


@pytest.mark.parametrize("args, kwargs, key", [
    ((1e9,), {}, "angle_from_normal_deg"), ((-1.0,), {}, "angle_from_normal_deg"),
    ((float("nan"),), {}, "angle_from_normal_deg"),
    ((0.0,), {"model": "glue"}, "model"), ((0.0,), {"width_m": float("nan")}, "width_m"),
    ((0.0,), {"width_m": 5.0}, "width_m"), ((0.0,), {"length_m": 0.0}, "length_m"),
    ((0.0,), {"grid": 0}, "grid"), ((0.0,), {"grid": 4096}, "grid"),
    ((0.0,), {"sigma_t_pa": -3.0}, "sigma_t_pa"), ((0.0,), {"mu": float("inf")}, "mu"),
    ((0.0,), {"arm_m": -0.1}, "arm_m"), ((0.0,), {"ramp_time_s": 0.0}, "ramp_time_s")])
def test_pulloff_refuses_what_the_cli_refuses(args, kwargs, key):
    with pytest.raises(climbsim.InputError, match=key):
        climbsim.pulloff(*args, **kwargs)


def test_a_callback_cannot_step_or_reset_its_own_simulation():
    class Reentrant(climbsim.Controller):
        def update(self, obs, cmd):
            self.sim.reset()

    c = Reentrant()
    c.sim = climbsim.Simulation(climbsim.scenario_from_dict(FLOOR), controller=c)
    with pytest.raises(RuntimeError, match="from a callback of its own controller"):
        c.sim.step()
    c.sim = None  # the cycle


def test_an_exception_in_a_callback_stops_the_run_until_reset():
    class Fails(climbsim.Controller):
        fail = True

        def update(self, obs, cmd):
            if self.fail:
                raise KeyError("from update")

    c = Fails()
    sim = climbsim.Simulation(climbsim.scenario_from_dict(FLOOR), controller=c)
    with pytest.raises(KeyError, match="from update"):
        sim.step()
    with pytest.raises(RuntimeError, match="part way through a step"):
        sim.step()  # not a second half-step on top of the first
    c.fail = False
    sim.reset()
    assert steps_until_false(sim) == 50


def climbsim_executable():
    build = os.environ.get("CLIMBSIM_BINARY_DIR", os.path.join(SOURCE, "build"))
    exe = os.path.join(build, "climbsim")
    if not os.access(exe, os.X_OK):
        pytest.skip("no climbsim executable at " + exe)
    return exe


# The ranges of the binding's optimise and pulloff arguments are those of the CLI's options,
# kept by CLI11 in tools/cmd_*.cc: a value just outside each bound is refused by both (exit
# code 2 of the command line, InputError naming the argument in Python).
CLI_RANGES = [
    ("pulloff", "angle_from_normal_deg", "--from-deg", 0.0, 180.0),
    ("pulloff", "width_m", "--width-m", 1e-4, 1.0),
    ("pulloff", "length_m", "--length-m", 1e-4, 1.0),
    ("pulloff", "grid", "--grid", 1, 1024),
    ("pulloff", "sigma_t_pa", "--sigma-t-pa", 1e-3, 1e12),
    ("pulloff", "mu", "--mu", 0.0, 1e3),
    ("pulloff", "arm_m", "--arm-m", 0.0, 1.0),
    ("pulloff", "ramp_time_s", "--ramp-time-s", 1e-3, 1e3),
    ("optimise", "threads", "--threads", 0, 1024),
    ("optimise", "max_evaluations", "--max-evaluations", 1, 100000000),
]


def just_outside(lo, hi):
    if isinstance(lo, int):
        return [lo - 1, hi + 1]
    return [lo - max(abs(lo) * 1e-6, 1e-9), hi * (1 + 1e-6)]


@pytest.mark.parametrize("verb, key, flag, lo, hi", CLI_RANGES)
def test_optimise_and_pulloff_ranges_are_the_cli_ranges(verb, key, flag, lo, hi, tmp_path):
    exe = climbsim_executable()
    scenario = os.path.join(SOURCE, "examples", "gecko_wall.yaml")
    for value in just_outside(lo, hi):
        out = str(tmp_path / "out")
        if verb == "pulloff":
            args = [exe, "pulloff", "--out", out, "--model", "bonds", "--quiet",
                    flag, repr(value)]
            call = lambda: climbsim.pulloff(**{"angle_from_normal_deg": 0.0, key: value})  # noqa: E731
        else:
            args = [exe, "optimise", scenario, "--out", out, "--quiet", flag, repr(value)]
            call = lambda: climbsim.optimise(scenario, out, **{key: value})  # noqa: E731
        r = subprocess.run(args, capture_output=True, text=True, timeout=60)
        assert r.returncode == 2 and flag in r.stderr + r.stdout, (value, r.stderr)
        with pytest.raises(climbsim.InputError, match=key):
            call()
