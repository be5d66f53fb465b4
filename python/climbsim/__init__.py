"""climbsim from Python: scenarios, runs, your own controller, optimise, pulloff, fit_adhesion.

    import climbsim
    s = climbsim.load_scenario("examples/gecko_wall.yaml")       # or scenario_from_dict({...})
    sim = climbsim.Simulation(s)                                  # optional controller=...
    summary = sim.run()                                           # dict (summary.json)
    t = sim.trajectory()                                          # dict: column -> numpy array
    e = sim.events()                                              # dict: column -> numpy array

A controller subclasses climbsim.Controller and overrides update(obs, cmd): obs holds numpy
copies of what the robot senses, cmd numpy arrays of what it commands, written back when
update returns; both raise ReferenceError when used after the call (docs/python.md).
"""
import json as _json

from ._core import (  # noqa: F401
    Command,
    Controller,
    InputError,
    Observation,
    Scenario,
    Simulation,
    SineOffsetController,
    StartPose,
    fit_adhesion,
    load_scenario,
    mjcf_dir,
    optimise,
    pulloff,
    scenario_from_yaml,
)


def scenario_from_dict(d, name="scenario_from_dict.yaml"):
    """A scenario from a dict with the keys of a scenario file (docs/scenario.md).

    JSON is YAML: the dict is written as JSON and parsed by the scenario loader, so a bad key
    raises climbsim.InputError like a bad file does. Relative paths resolve against the
    current folder; `name` is the file name error messages give.
    """
    return scenario_from_yaml(_json.dumps(d), name)
