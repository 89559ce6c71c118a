"""The bagdem Python package (python/bagdem, docs/python.md), run by ctest (PythonPackage) on Debian's
python3 with BAGDEM set to the built binary and PYTHONPATH to the clone's python/.

1. The worked example (python/examples/design_a_damper.py) runs from a structure written in Python
   to a design: its predicted reductions match the rolling ball's analytic 2/7-mass figure within
   0.01 dB, the lighter ball ranks first, and the chosen case loads with it.
2. Tables come back with their headers as written, numbers as floats, text as text, units kept.
3. Overrides are written as TOML (quantities keep their units) and never change the Case they came
   from; a case bagdem refuses raises BagdemError with exit code 2 and bagdem's message.
4. A run's progress reaches the caller line by line; its summary and results.h5 read back.
"""
import math
import os
import sys

import numpy as np
import pytest

import bagdem
from bagdem.command import option_args, toml_value

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "python", "examples"))
import design_a_damper  # noqa: E402


def test_the_example_designs_the_rolling_ball_as_the_analytic_figure(tmp_path):
    case, coupled, design, chosen = design_a_damper.main(str(tmp_path))
    # The coupled run: the ball adds 2/7 of its mass (10 mm: 4.08 g) at every frequency.
    ratio = coupled.reduced["M_eff_ratio [1]"]
    assert len(ratio) >= 3
    assert np.all(np.abs(ratio - 2 / 7) < 0.01 * 2 / 7), ratio.tolist()
    table = design.design
    ranked = table[table["status"] == "ranked"]
    assert list(ranked["particles.ball.diameter"]) == ["6 mm", "8 mm"], "the lighter ball raises the peak less"
    for diameter, predicted in zip(ranked["particles.ball.diameter"], ranked["objective_dB [dB]"]):
        expected = design_a_damper.analytic_db(float(diameter.split()[0]) * 1e-3)
        assert abs(predicted - expected) < 0.01, (diameter, predicted, expected)
    assert table.loc[table["particles.ball.diameter"] == "10 mm", "status"].item() == "over budget"
    assert math.isfinite(ranked["dem_objective_dB [dB]"].iloc[0]), "the best run coupled"
    assert os.path.isfile(design.file("design.png"))
    assert "diameter 0.006 .. 0.006 m" in chosen.check()


def test_tables_keep_their_headers_numbers_text_and_units(tmp_path):
    path = tmp_path / "peaks.csv"
    path.write_text("mode [1],reduction_dB [dB],bag.balls.diameter,e_method [text],status\n1,14.9,4 mm,impact,done\n3,,8 mm,eq19a,failed\n")
    frame = bagdem.read_table(str(path))
    assert list(frame.columns) == ["mode [1]", "reduction_dB [dB]", "bag.balls.diameter", "e_method [text]", "status"]
    assert frame["reduction_dB [dB]"].iloc[0] == 14.9 and math.isnan(frame["reduction_dB [dB]"].iloc[1])
    assert frame["mode [1]"].tolist() == [1, 3]
    assert frame["bag.balls.diameter"].tolist() == ["4 mm", "8 mm"]
    assert frame["e_method [text]"].tolist() == ["impact", "eq19a"]
    assert frame.attrs["units"]["reduction_dB [dB]"] == "dB" and frame.attrs["units"]["status"] == ""
    results = bagdem.Results(str(tmp_path))
    assert results.peaks["mode [1]"].tolist() == [1, 3]
    with pytest.raises(FileNotFoundError, match="has no reduced.csv; it has: peaks"):
        results.reduced


def test_overrides_are_toml_and_a_refused_case_raises_with_exit_2(tmp_path):
    assert toml_value("8 mm") == '"8 mm"' and toml_value(0.08) == "0.08" and toml_value(True) == "true"
    assert toml_value(["-40 mm", 0, 1.5]) == '["-40 mm", 0, 1.5]' and toml_value(np.float64(0.5)) == "0.5"
    with pytest.raises(TypeError):
        toml_value({"a": 1})
    assert option_args({"gamma": (0.5, 20), "seeds": 3, "verify": True, "zip": False, "key": ["a", "b"], "window_time": 0}) == [
        "--gamma", "0.5,20", "--seeds", "3", "--verify", "--key", "a", "--key", "b", "--window-time", "0"]
    base = bagdem.Case(os.path.join(ROOT, "cases", "box-damper"))
    shaken = base.set({"cavity.motion.amplitude": "2 mm"})
    assert base.overrides == {} and shaken.set_args() == ["--set", 'cavity.motion.amplitude="2 mm"']
    assert "X = 0.002 m" in shaken.check()
    with pytest.raises(bagdem.BagdemError) as refused:
        base.set({"cavity.motion.amplitude": "2 kg"}).check()
    assert refused.value.code == 2
    assert "cavity.motion.amplitude" in refused.value.message and "2 kg" in refused.value.message
    with pytest.raises(FileNotFoundError, match="no case.toml"):
        bagdem.Case(str(tmp_path))


def test_a_run_shows_its_progress_and_reads_back(tmp_path):
    lines = []
    case = bagdem.Case(os.path.join(ROOT, "cases", "box-damper"), {"simulation.duration": "0.01 s", "simulation.settle": "0.005 s"})
    out = case.run(str(tmp_path / "run"), progress=lines.append)
    assert any("%" in line and "ETA" in line for line in lines), lines
    assert out.summary["status"] == "complete" and out.summary["particles"] == 100
    h5 = out.h5
    t = h5["cavity/time"]
    assert "cavity/position" in h5 and t.ndim == 1 and len(t) > 10 and np.all(np.diff(t) > 0)
    assert h5["frames/position"].shape[1:] == (100, 3)
    with pytest.raises(KeyError, match="has no dataset"):
        h5["cavity/nothing"]
