"""A Scenario's keys from Python (python/scenario_keys.cc) and the command's stiffness."""
import os
import re

import numpy as np
import pytest

import climbsim

SOURCE = os.environ.get("CLIMBSIM_SOURCE_DIR",
                        os.path.join(os.path.dirname(__file__), "..", ".."))

FLOOR = {"robot": "gecko", "scene": "floor", "duration_s": 0.05,
         "cpg": {"gait": "trot", "frequency_hz": 1.0}}


def test_every_key_reads_and_a_write_reaches_the_run():
    s = climbsim.load_scenario(os.path.join(SOURCE, "examples", "gecko_wall.yaml"))
    assert s["cpg.frequency_hz"] == 0.6
    assert s["cpg.gait"] == "lateral_sequence"
    keys = s.keys()
    assert "cpg.frequency_hz" in keys and "duration_s" in keys and "seed" in keys
    assert "optimise.parameters[0].key" in keys
    for k in keys:  # every listed key reads back
        s[k]
    s["cpg.frequency_hz"] = 0.8
    assert s["cpg.frequency_hz"] == 0.8
    assert "frequency_hz: 0.8\n" in s.to_yaml()
    s["duration_s"] = np.float64(0.02)  # NumPy scalars are numbers
    s["outputs.trajectory_rate_hz"] = 0
    assert climbsim.Simulation(s).run()["steps"] == 20


def test_lists_maps_and_optional_blocks():
    s = climbsim.scenario_from_dict(FLOOR)
    assert "reflex" not in s and s.get("reflex.preload.enabled") is None
    assert s.get("reflex.preload.enabled", 7) == 7
    s["reflex.preload.enabled"] = False  # the block is made, the rest of it defaults
    assert s["reflex.preload.enabled"] is False and s["reflex.gto.enabled"] is True
    del s["reflex"]
    assert "reflex" not in s
    s["cpg.stride_rad"] = [0.3, 0.0, 0.0]
    s["cpg.stride_rad[1]"] = 0.05
    assert s["cpg.stride_rad"] == [0.3, 0.05, 0.0]
    del s["cpg.frequency_hz"]  # back to its default
    assert s["cpg.frequency_hz"] == climbsim.scenario_from_dict(
        {"robot": "gecko", "scene": "floor", "duration_s": 1, "cpg": {}})["cpg.frequency_hz"]
    with pytest.raises(climbsim.InputError, match="applies to the incline scene only"):
        s["scene.incline_deg"] = 10  # refused like the file's: the floor has no incline


def file_message(text):
    """The loader's message for a file, without its place (file:line:col)."""
    with pytest.raises(climbsim.InputError) as e:
        climbsim.scenario_from_yaml(text, "k.yaml")
    return re.sub(r"^.*?k\.yaml(:\d+)*: ", "", str(e.value))


FLOOR_TEXT = "robot: gecko\nscene: floor\nduration_s: 0.05\ncpg: {gait: trot, frequency_hz: 1.0}\n"


@pytest.mark.parametrize("key, value, line", [
    ("cpg.frequency_hz", "abc", "cpg: {gait: trot, frequency_hz: abc}"),
    ("cpg.frequency_hz", -1.0, "cpg: {gait: trot, frequency_hz: -1}"),
    ("cpg.frequncy_hz", 1.0, "cpg: {gait: trot, frequency_hz: 1.0, frequncy_hz: 1}"),
    ("cpg.oscillator", "banana", "cpg: {gait: trot, frequency_hz: 1.0, oscillator: banana}"),
    ("duration_s", float("nan"), "duration_s: .nan"),
])
def test_a_write_is_refused_with_the_files_text(key, value, line):
    s = climbsim.scenario_from_dict(FLOOR)
    before = s.to_yaml()
    top = line.split(":")[0]
    text = "".join(l if not l.startswith(top + ":") else line + "\n"
                   for l in FLOOR_TEXT.splitlines(keepends=True))
    want = file_message(text)
    with pytest.raises(climbsim.InputError) as e:
        s[key] = value
    assert str(e.value).endswith(want), (str(e.value), want)
    assert s.to_yaml() == before  # unchanged


def test_missing_keys_and_bad_key_syntax():
    s = climbsim.scenario_from_dict(FLOOR)
    with pytest.raises(KeyError):
        s["cpg.nope"]
    with pytest.raises(climbsim.InputError, match=r"cpg\.stride_rad is not in the file"):
        s["cpg.stride_rad[0]"] = 0.3  # a list the scenario does not hold: set it whole
    s["cpg.stride_rad"] = (0.3, 0, 0)
    with pytest.raises(climbsim.InputError, match=r"cpg\.stride_rad\[9\] is not in the file"):
        s["cpg.stride_rad[9]"] = 1.0
    with pytest.raises(climbsim.InputError, match="is not a dotted key"):
        s["cpg..x"] = 1.0
    with pytest.raises(TypeError):
        s["duration_s"] = object()


def test_to_dict_is_the_same_scenario():
    s = climbsim.load_scenario(os.path.join(SOURCE, "examples", "gecko_wall.yaml"))
    d = s.to_dict()
    assert d["cpg"]["frequency_hz"] == 0.6
    assert climbsim.scenario_from_dict(d).to_yaml() == s.to_yaml()


class Soft(climbsim.Controller):
    """Holds the start pose with the LF hip_pitch servo at a quarter of its stiffness."""

    def __init__(self):
        super().__init__()
        self.seen = None

    def control_period_s(self):
        return 0.01

    def update(self, obs, cmd):
        if self.seen is None:
            self.seen = cmd.kp_scale.copy()
        cmd.kp_scale[1] = 0.25
        cmd.kp_scale[2] = 2.0  # above the servo's own kp: clamped to 1


def test_a_python_controller_sets_a_servos_stiffness():
    s = climbsim.scenario_from_dict({"robot": "gecko", "scene": "floor", "duration_s": 0.05})
    c = Soft()
    sim = climbsim.Simulation(s, controller=c)
    sim.run()
    assert list(c.seen) == [1.0] * 12  # full stiffness until a controller says otherwise
    kp = sim.command()["kp_scale"]
    assert kp[1] == 0.25 and kp[2] == 2.0 and kp[0] == 1.0
