"""Running the bagdem binary: where it is, a command line from Python values, progress shown as it
goes, and failures raised with bagdem's own message and exit code."""
import os
import signal
import subprocess
import sys
import threading

# The repository's root (python/bagdem/ is two levels below it): a clone's build/bagdem is found
# without installing anything.
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))

# bagdem's exit codes (bagdem --help).
EXIT_MEANING = {1: "system error (I/O, a full disk)", 2: "bad input (case or command line)",
                3: "a run went unstable or a point failed", 130: "stopped by SIGINT", 143: "stopped by SIGTERM"}


class BagdemError(RuntimeError):
    """A bagdem command that did not succeed: `code` is its exit code (negative: killed by that
    signal), `message` what it printed on stderr without the progress lines (its last 200 lines),
    `command` the command line."""

    def __init__(self, command, code, message):
        self.command, self.code, self.message = list(command), code, message
        meaning = f"killed by signal {-code}" if code < 0 else EXIT_MEANING.get(code, "failed")
        name = command[1] if len(command) > 1 else ""
        super().__init__(f"bagdem {name} exited {code} ({meaning}):\n{message.rstrip()}")

    def __reduce__(self):  # pickled whole (a process pool sends it back to its parent)
        return (BagdemError, (self.command, self.code, self.message))


def binary():
    """The bagdem executable: $BAGDEM if set, else the clone's build/bagdem ($BAGDEM_BUILD_DIR/bagdem
    when that is set, as tools/ read it)."""
    path = os.environ.get("BAGDEM") or os.path.join(os.environ.get("BAGDEM_BUILD_DIR", os.path.join(ROOT, "build")), "bagdem")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        raise FileNotFoundError(f"no bagdem executable at {path}: build it (tools/test or tools/demo builds build/bagdem), "
                                "or set BAGDEM to its path")
    return path


def toml_value(value):
    """A Python value as the TOML text --set reads: "8 mm" (a quantity), 0.08, true, [1, 3],
    ["-40 mm", "0 mm", "0 mm"], a dict as an inline table. Strings are quoted, so a unit is always kept with its number;
    numpy scalars are written as the Python numbers they hold."""
    if getattr(value, "ndim", 0) > 0:  # a numpy array: its elements, as a list
        value = value.tolist()
    elif hasattr(value, "item") and not isinstance(value, (list, tuple, str)):  # a numpy scalar
        value = value.item()
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if value != value or value in (float("inf"), float("-inf")):
            raise ValueError(f"{value!r} is not a value a case can take")
        return repr(value)
    if isinstance(value, str):
        escaped = "".join(c if c.isprintable() and c not in '"\\' else ("\\" + c if c in '"\\' else f"\\u{ord(c):04x}")
                          for c in value)
        return '"' + escaped + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):  # an inline table: {kind = "harmonic", ...}, a [[dampers]] entry
        for k in value:
            if not isinstance(k, str) or not k or not all(c.isalnum() or c in "_-" for c in k):
                raise ValueError(f"{k!r} is not a key a case table can have (letters, digits, '_', '-')")
        return "{" + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"cannot write {value!r} ({type(value).__name__}) as a case value: use a number, a string "
                    "with its unit (\"8 mm\"), a bool, a dict (a table) or a list of them")


def option_args(options):
    """Keyword options as command-line arguments: gamma=(0.5, 20) -> --gamma 0.5,20; seeds=3 ->
    --seeds 3; verify=True -> --verify; a list for a repeatable option (key=[...]) -> --key each;
    underscores become dashes (window_time -> --window-time). None and False leave an option out."""
    out = []
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        if hasattr(value, "item") and not isinstance(value, (list, tuple, str)):  # a numpy scalar
            value = value.item()
        if value is None or value is False:
            continue
        if value is True:
            out.append(flag)
        elif isinstance(value, list):
            for v in value:
                out += [flag, str(v)]
        elif isinstance(value, tuple):
            out += [flag, ",".join(str(v) for v in value)]
        else:
            out += [flag, str(value)]
    return out


def is_progress(line):
    """bagdem's progress lines on stderr (a run's percentages, a study's counts), shown as they come
    but not kept in an error's message."""
    s = line.strip()
    return (s[:1].isdigit() and "%" in s.split()[0]) or s.startswith(("sweep: ", "characterize: ", "design: ", "calibrate: "))


def run(args, progress=True, cwd=None):
    """Runs `bagdem ARGS...` (args without the executable) and returns its stdout. Progress on stderr
    is passed to `progress` line by line: True prints it to sys.stderr, False drops it, a callable
    receives each line. Raises BagdemError with the exit code and the message when it fails. An
    interrupt (Ctrl-C, KeyboardInterrupt) is passed on to bagdem, which stops as it does on SIGINT
    (a run leaves its checkpoint), and is raised once bagdem has stopped."""
    cmd = [binary()] + [str(a) for a in args]
    show = (lambda line: sys.stderr.write(line)) if progress is True else (progress or (lambda line: None))
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, encoding="utf-8", errors="replace",
                            cwd=cwd, bufsize=1)
    out, kept = [], []
    reader = threading.Thread(target=lambda: out.extend(proc.stdout), daemon=True)
    reader.start()
    try:
        for line in proc.stderr:
            show(line)
            if not is_progress(line):
                kept.append(line)
        reader.join()
        code = proc.wait()
    except BaseException:
        stop(proc)
        raise
    if code != 0:
        raise BagdemError(cmd, code, "".join(kept[-200:]) or "".join(out[-20:]))
    return "".join(out)


def stop(proc):
    """Stops a bagdem child as Ctrl-C would (SIGINT: a run writes its checkpoint, a study stops its
    points), then harder if it has not stopped within 30 s."""
    if proc.poll() is not None:
        return
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
