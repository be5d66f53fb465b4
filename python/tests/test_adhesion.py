"""climbsim.pulloff with law= and climbsim.fit_adhesion: the same numbers as the command line."""
import csv
import os

import pytest

import climbsim

SOURCE = os.environ.get("CLIMBSIM_SOURCE_DIR",
                        os.path.join(os.path.dirname(__file__), "..", ".."))
DATA = os.path.join(SOURCE, "examples", "pad_pulloff.csv")
TABLE = {"angle_from_normal_deg": [0, 30, 60, 90], "pulloff_n": [2.1, 2.4, 3.3, 1.2],
         "width_m": 0.02, "length_m": 0.02}


def test_pulloff_angle_is_from_the_normal_for_every_law():
    # 0 deg pulls straight off: the von Mises pad lets go at sigma_T * A.
    r = climbsim.pulloff(angle_from_normal_deg=0.0, model="bonds")
    assert r["force_n"] == pytest.approx(r["capacity_n"], rel=0.02)
    # The frictional pad cannot hold a straight pull, and holds tau_max * A at 90 deg.
    assert climbsim.pulloff(0.0, law="frictional")["force_n"] == 0.0
    f = climbsim.pulloff(90.0, law="frictional", shear_limit_pa=8e3)
    assert f["force_n"] == pytest.approx(8e3 * 0.025 ** 2, rel=1e-5)
    # The designer's table on its own pad: the table, interpolated at 45 deg.
    for angle, force in [(0, 2.1), (30, 2.4), (60, 3.3), (90, 1.2), (45, 2.85)]:
        t = climbsim.pulloff(angle, law="tabulated", width_m=0.02, table=TABLE)
        assert t["force_n"] == pytest.approx(force, rel=1e-5)
    with pytest.raises(climbsim.InputError, match="law"):
        climbsim.pulloff(0.0, law="glue")


def test_fit_adhesion_returns_what_the_command_writes(tmp_path):
    out = tmp_path / "fit"
    r = climbsim.fit_adhesion(DATA, "von_mises", out_dir=str(out))
    assert not r["represents"] and "cannot represent" in r["verdict"]
    with open(out / "parameters.csv") as f:
        row = next(csv.DictReader(f))
    assert row["key"] == "sigma_t_pa"
    assert float(row["value"]) == pytest.approx(r["parameters"][0]["value"], rel=1e-5)
    assert (out / "fitted.yaml").read_text() == r["fitted_yaml"]
    t = climbsim.fit_adhesion(DATA, "tabulated")
    assert t["represents"]
    assert t["predicted_n"] == pytest.approx([2.1, 2.4, 3.3, 1.2], rel=0.02)
    with pytest.raises(climbsim.InputError, match="angle_from_normal_deg"):
        bad = tmp_path / "bare.csv"
        bad.write_text("angle,force_n\n0,2\n")
        climbsim.fit_adhesion(str(bad), "tabulated", width_m=0.02)
