"""A case directory with overrides, and every bagdem command run on it."""
import os
import tempfile

from . import command
from .results import Results


class Case:
    """A case directory (it holds case.toml) and overrides of its keys, applied to every command run
    on it as `--set key=value`. Values are Python values: a quantity is a string with its unit
    ("8 mm"), plain numbers are SI, lists and bools as in TOML.

        pipe = bagdem.Case("cases/pipe-beanbag", {"excitation.amplitude": "0.1 N"})
        heavier = pipe.set({"bag.balls.mass_ratio": 0.08})   # a new Case; pipe is unchanged
        print(heavier.check())                               # the resolved scene, as bagdem check
        out = heavier.run("out/heavier")                     # Results: tables as pandas frames
    """

    def __init__(self, path, overrides=None):
        path = os.path.abspath(path)
        if os.path.basename(path) == "case.toml":
            path = os.path.dirname(path)
        if not os.path.isfile(os.path.join(path, "case.toml")):
            raise FileNotFoundError(f"{path}: no case.toml (a case is a directory that holds one; docs/case-schema.md)")
        self.path = path
        self.overrides = dict(overrides or {})

    @classmethod
    def write(cls, path, text, overrides=None):
        """A new case: writes `text` as PATH/case.toml (the directory made if needed; an existing
        case.toml replaced whole, through a temporary name) and returns the Case."""
        os.makedirs(path, exist_ok=True)
        fd, part = tempfile.mkstemp(dir=path, prefix=".case.toml.")
        with os.fdopen(fd, "w") as f:
            f.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(part, 0o666 & ~umask)  # as open() would make it, not mkstemp's 0600
        os.replace(part, os.path.join(path, "case.toml"))
        return cls(path, overrides)

    def set(self, overrides):
        """A copy with more overrides (a later value of a key replaces an earlier one)."""
        return Case(self.path, {**self.overrides, **overrides})

    def set_args(self):
        """The overrides as bagdem's --set arguments."""
        out = []
        for key, value in self.overrides.items():
            out += ["--set", f"{key}={command.toml_value(value)}"]
        return out

    def __repr__(self):
        return f"Case({self.path!r}, {self.overrides!r})"

    # ---- commands ----------------------------------------------------------------------------
    # Each runs `bagdem COMMAND CASE --set ... OPTIONS --out OUT`, showing progress (progress=False
    # keeps quiet, a callable receives each line), and returns the output directory as Results.
    # Options are keyword arguments named as on the command line (docs/commands.md).

    def check(self):
        """The resolved scene (`bagdem check`): SI units, defaults filled, what is modelled; raises
        BagdemError (code 2, bagdem's message) for a case bagdem refuses."""
        return command.run(["check", self.path] + self.set_args(), progress=False)

    def command(self, name, out, progress=True, **options):
        """Runs `bagdem NAME CASE ... --out OUT` with the options and returns Results(OUT); with
        check=True (a study's plan, nothing run) the plan bagdem printed, as text."""
        printed = command.run([name, self.path] + self.set_args() + command.option_args(options) + ["--out", os.path.abspath(out)],
                              progress=progress)
        return printed if options.get("check") else Results(out)

    def run(self, out, progress=True, **options):
        """`bagdem run`: one run (a coupled case runs its frequency sweep)."""
        return self.command("run", out, progress, **options)

    def sweep(self, out, vary=None, progress=True, **options):
        """`bagdem sweep`: a study over `vary` = {key: [values]} (a grid; zip=True takes them
        together), seeds=N for an ensemble per point."""
        return self.command("sweep", out, progress, vary=vary_args(vary), **options)

    def characterize(self, out, progress=True, **options):
        """`bagdem characterize`: the damper's effective-field map (gamma=(lo, hi), band=(lo, hi), ...)."""
        return self.command("characterize", out, progress, **options)

    def predict(self, out, maps, progress=True, **options):
        """`bagdem predict --map MAP`: the structure's response with the map's damper, without DEM; a
        case of several dampers takes `maps={"tip": MAP, "mid": MAP2}` (--map NAME=MAP each)."""
        if isinstance(maps, dict):
            given = [f"{name}={os.path.abspath(str(d))}" for name, d in maps.items()]
        else:
            given = os.path.abspath(str(maps))
        return self.command("predict", out, progress, map=given, **options)

    def design(self, out, vary=None, progress=True, **options):
        """`bagdem design`: the bag searched over `vary` (and positions) under a mass budget."""
        return self.command("design", out, progress, vary=vary_args(vary), **options)

    def calibrate(self, out, progress=True, **options):
        """`bagdem calibrate`: a key (or several, with maps=[...]) fitted to measured reductions."""
        if "maps" in options and isinstance(options["maps"], (list, tuple)):
            maps = [os.path.abspath(str(m)) for m in options.pop("maps")]
            return self._with_list("calibrate", out, progress, "--maps", maps, options)
        return self.command("calibrate", out, progress, **options)

    def trade(self, out, progress=True, **options):
        """`bagdem trade`: the speed/accuracy trade of the case."""
        return self.command("trade", out, progress, **options)

    def drop(self, out, progress=True, **options):
        """`bagdem drop`: the drop test of the case's bag."""
        return self.command("drop", out, progress, **options)

    def _with_list(self, name, out, progress, flag, values, options):
        """A command whose option takes several values at once (--maps A B C)."""
        command.run([name, self.path] + self.set_args() + command.option_args(options) + [flag] + values +
                    ["--out", os.path.abspath(out)], progress=progress)
        return Results(out)


def vary_args(vary):
    """{key: [values]} as --vary arguments (KEY=V1,V2,...), values written as TOML."""
    if vary is None:
        return None
    def listed(values):  # one value, or any sequence of them (a list, a numpy array)
        return [values] if isinstance(values, str) or not hasattr(values, "__iter__") else list(values)
    return [f"{key}=" + ",".join(command.toml_value(v) for v in listed(values)) for key, values in vary.items()]
