"""The bagdem Python package (python/bagdem, docs/python.md), run by ctest (PythonPackage) on Debian's
python3 with BAGDEM set to the built binary and PYTHONPATH to the clone's python/.

1. The worked example (python/examples/design_a_damper.py) runs from a structure written in Python
   to a design: its predicted reductions match the rolling ball's analytic 2/7-mass figure within
   0.01 dB, the lighter ball ranks first, and the chosen case loads with it.
2. Tables come back with their headers as written, numbers as floats (bagdem's nan as NaN), text as
   text, units kept; a unit's column holding text is refused; a missing table is an AttributeError.
3. Overrides are written as TOML (quantities keep their units, numpy scalars their numbers) and
   never change the Case they came from; a case bagdem refuses raises BagdemError with exit code 2
   and bagdem's message, which survives pickling.
4. A run's progress reaches the caller line by line; its summary and results.h5 read back. An
   interrupt stops bagdem before it is raised.
5. A case of several dampers (a dict per [[dampers]] entry) runs, and each damper's record reads
   back by its name (Results.dampers).
"""
import math
import os
import pickle
import subprocess
import sys
import time

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
    path.write_text("mode [1],reduction_dB [dB],e [1],bag.balls.diameter,e_method [text],status,point\n"
                    "1,14.9,nan,4 mm,impact,done,0\n3,,-nan,8 mm,eq19a,failed,1\n")
    frame = bagdem.read_table(str(path))
    assert list(frame.columns) == ["mode [1]", "reduction_dB [dB]", "e [1]", "bag.balls.diameter", "e_method [text]", "status", "point"]
    assert frame["reduction_dB [dB]"].iloc[0] == 14.9 and math.isnan(frame["reduction_dB [dB]"].iloc[1])
    assert frame["e [1]"].dtype == float and frame["e [1]"].isna().all(), "bagdem's nan and -nan are NaN, not text"
    assert frame["mode [1]"].tolist() == [1, 3] and frame["mode [1]"].dtype == float
    assert frame["point"].tolist() == [0, 1]
    assert frame["bag.balls.diameter"].tolist() == ["4 mm", "8 mm"]
    assert frame["e_method [text]"].tolist() == ["impact", "eq19a"]
    assert frame.attrs["units"]["reduction_dB [dB]"] == "dB" and frame.attrs["units"]["status"] == ""
    results = bagdem.Results(str(tmp_path))
    assert results.peaks["mode [1]"].tolist() == [1, 3]
    with pytest.raises(AttributeError, match="has no reduced.csv; it has: peaks"):
        results.reduced
    assert not hasattr(results, "reduced") and getattr(results, "sweep", None) is None
    (tmp_path / "design-pairs.csv").write_text("rank [1],status,bag.balls.mass_ratio,position_xL [1],bag.balls.mass_ratio_2,position_xL_2 [1]\n"
                                               "1,ranked,0.04,0.56,0.04,0.92\n")
    assert results.design_pairs["position_xL_2 [1]"].tolist() == [0.92]
    with pytest.raises(FileNotFoundError, match="has no reduced.csv"):
        results.table("reduced")
    # A number column holding text is refused, naming it; an empty file too.
    (tmp_path / "sweep.csv").write_text("frequency [Hz],peak [m/N]\n80,0.1\n81,oops\n")
    with pytest.raises(ValueError, match="column 'peak \\[m/N\\]' row 2: 'oops' is not a number"):
        results.sweep
    (tmp_path / "trade.csv").write_text("")
    with pytest.raises(ValueError, match="empty"):
        results.trade
    # A study's points in order, past point-999.
    for name in ("point-1000", "point-002", "point-010", "point-x"):
        (tmp_path / name).mkdir()
    assert [os.path.basename(p.path) for p in results.points] == ["point-002", "point-010", "point-1000"]


def test_overrides_are_toml_and_a_refused_case_raises_with_exit_2(tmp_path):
    assert toml_value("8 mm") == '"8 mm"' and toml_value(0.08) == "0.08" and toml_value(True) == "true"
    assert toml_value(["-40 mm", 0, 1.5]) == '["-40 mm", 0, 1.5]' and toml_value(np.float64(0.5)) == "0.5"
    assert toml_value(np.array([-0.04, 0.0, 0.0])) == "[-0.04, 0.0, 0.0]"
    assert toml_value(np.int64(3)) == "3" and toml_value(np.bool_(True)) == "true" and toml_value('a"b\nc') == '"a\\"b\\u000ac"'
    assert toml_value({"kind": "harmonic", "amplitude": "1 N"}) == '{kind = "harmonic", amplitude = "1 N"}'
    with pytest.raises(TypeError):
        toml_value(object())
    with pytest.raises(ValueError):
        toml_value(float("nan"))
    assert option_args({"zip": np.bool_(True), "check": np.False_}) == ["--zip"]
    assert bagdem.case.vary_args({"k": "6 mm", "x": np.array([0.5, 1.0])}) == ['k="6 mm"', "x=0.5,1.0"]
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
    # The error survives a process pool (pickled), with its code and message.
    again = pickle.loads(pickle.dumps(refused.value))
    assert again.code == 2 and again.message == refused.value.message and again.command == refused.value.command
    # A study's plan (check=True) comes back as text; nothing runs.
    plan = base.sweep(str(tmp_path / "plan"), vary={"cavity.motion.amplitude": ["1 mm", "2 mm"]}, check=True, progress=False)
    assert "point-000" in plan and "point-001" in plan and not (tmp_path / "plan" / "point-000").exists()


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
    assert np.array_equal(h5["/cavity/time"], t)


def test_several_dampers_are_written_and_read_per_damper(tmp_path):
    # A second damper given from Python ([[dampers]] as a list of dicts), run, and each damper's
    # record read back by its name; the structure's figures are the case's own damper's.
    case = bagdem.Case(os.path.join(ROOT, "cases", "stepped-beam"), {
        "excitation": {"kind": "harmonic", "amplitude": "0.05 N", "frequency": "70 Hz", "start": "steady"},
        "simulation.duration": "0.004 s", "simulation.settle": "0.004 s",
        "dampers": [{"name": "mid", "set": ['primary.attach = "0.335 m"']}]})
    out = case.run(str(tmp_path / "run"))
    assert list(out.dampers) == ["mid"]
    mid = out.dampers["mid"]
    assert mid.summary["damper"] == "mid" and "structure" not in mid.summary
    assert out.summary["damper"] == "1" and "structure" in out.summary
    assert mid.h5["cavity/time"].shape == out.h5["cavity/time"].shape
    assert bagdem.Results(str(tmp_path / "run")).dampers.keys() == {"mid"}
    with pytest.raises(ValueError, match="not a key"):
        toml_value({"a b": 1})
    # The pair predicted from a map per damper (constant maps: a mass and a dashpot each).
    for name, c in (("tip", 2.0), ("mid", 0.5)):
        (tmp_path / name).mkdir()
        rows = [f"{g},{f},0.01,0,{c},0" for g in (1e-4, 100) for f in (50, 480)]
        (tmp_path / name / "map.csv").write_text("gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m],C_eff_ci95 [N s/m]\n"
                                                 + "\n".join(rows) + "\n")
    pair = bagdem.Case(os.path.join(ROOT, "cases", "stepped-beam-pair"))
    predicted = pair.predict(str(tmp_path / "p"), maps={"tip": tmp_path / "tip", "mid": tmp_path / "mid"}, points=50)
    assert predicted.predict_peaks["mode [1]"].tolist() == [1, 2]
    assert (predicted.predict["cavity_amplitude_mid [m]"] > 0).all()


def test_an_interrupt_stops_bagdem_before_it_is_raised(tmp_path):
    out = tmp_path / "stopped"

    def interrupt(line):
        if "%" in line:
            raise KeyboardInterrupt

    case = bagdem.Case(os.path.join(ROOT, "cases", "box-damper"), {"simulation.duration": "2 s"})
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        case.run(str(out), progress=interrupt)
    assert time.monotonic() - started < 60, "a 2-s run takes minutes: it was stopped"
    running = subprocess.run(["pgrep", "-f", str(out)], capture_output=True, text=True).stdout
    assert running == "", "no bagdem left running"
    assert not (out / "summary.json").exists()
