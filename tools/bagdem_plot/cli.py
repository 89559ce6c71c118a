"""tools/plot's command line: every figure the directory has the data for, written once all are drawn."""
import argparse
import os
import sys

from .calibrate import plot_calibrate
from .compare import plot_compare
from .design import plot_design
from .effective_map import plot_map
from .prediction import plot_prediction
from .figure import DPI, plt
from .reduced import plot_reduced
from .response import plot_response
from .study import plot_study
from .tables import BadInput
from .trade import plot_trade


def main(argv):
    p = argparse.ArgumentParser(
        prog="tools/plot",
        description="PNG figures (150 dpi) from bagdem's output tables: response.png (sweep.csv), reduced.png "
                    "(reduced.csv), compare.png (compare.csv), study_<key>.png (a study's peaks.csv and "
                    "reduced.csv), trade.png (trade.csv), calibrate.png (calibrate.csv), map.png (map.csv), predict.png (predict.csv), design.png (design.csv). Prints the paths written.")
    p.add_argument("dir", metavar="DIR", help="a run's or a study's output directory")
    p.add_argument("--out", metavar="PNG_DIR", help="where to write the figures (default: DIR)")
    p.add_argument("--x", metavar="COLUMN", help="the x axis of reduced.png: a column of reduced.csv (default: gamma)")
    a = p.parse_args(argv)
    if not os.path.isdir(a.dir):
        raise BadInput(f"{a.dir}: not a directory; DIR is a run's or a study's output directory")
    tables = ("sweep.csv", "bare_curve.csv", "peaks.csv", "reduced.csv", "compare.csv", "peaks_ensemble.csv",
              "reduced_ensemble.csv", "trade.csv", "calibrate.csv", "map.csv", "predict.csv", "design.csv")
    if not any(os.path.isfile(os.path.join(a.dir, n)) for n in tables):
        raise BadInput(f"{a.dir}: nothing to plot: none of {', '.join(tables)} is there")
    out_dir = a.out or a.dir
    # Every table is read and checked while drawing; nothing is written unless all of it is good.
    figures = []
    plot_response(a.dir, out_dir, figures)
    plot_reduced(a.dir, out_dir, a.x, figures)
    plot_compare(a.dir, out_dir, figures)
    if not os.path.isfile(os.path.join(a.dir, "map.csv")):  # a map's runs are its cells, drawn by map.png
        plot_study(a.dir, out_dir, figures)
    plot_trade(a.dir, out_dir, figures)
    plot_calibrate(a.dir, out_dir, figures)
    plot_map(a.dir, out_dir, figures)
    plot_prediction(a.dir, out_dir, figures)
    plot_design(a.dir, out_dir, figures)
    if not figures:
        raise BadInput(f"{a.dir}: no figure drawn: its tables have no rows to plot")
    for _, path in figures:  # before anything is written: a file of the user's under a figure's name stays
        refuse_other_file(path)
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as e:
        raise OSError(f"--out {out_dir}: cannot create the directory: {e.strerror}") from e
    for fig, path in figures:
        # Written whole under a temporary name, then renamed: a stopped plot leaves the earlier figure.
        part = path + ".part.png"
        try:
            fig.savefig(part, dpi=DPI, metadata={"Software": SOFTWARE})
            os.replace(part, path)
        finally:
            if os.path.exists(part):
                os.remove(part)
        plt().close(fig)
        print(path)
    return 0


SOFTWARE = "bagdem tools/plot"


def refuse_other_file(path):
    """A figure is written only over a figure tools/plot wrote, a PNG whose Software text is tools/plot's;
    anything else (a file of the user's, a figure of theirs or of a tools/plot before it named itself,
    a link, a directory) is bad input."""
    if not os.path.lexists(path):
        return
    ours = False
    if os.path.isfile(path) and not os.path.islink(path):
        with open(path, "rb") as f:
            head = f.read(4096)
        ours = head.startswith(b"\x89PNG\r\n\x1a\n") and b"tEXtSoftware\x00" + SOFTWARE.encode() in head
    if not ours:
        raise BadInput(f"{path}: holds a file that is not a figure of tools/plot (a file of yours, another program's, or a "
                       "figure of a tools/plot before figures were marked), which it would replace: give another --out, or "
                       "move that file away")


def run(argv):
    """main with bagdem's exit codes: 2 for bad input, 1 for a system error."""
    try:
        return main(argv)
    except BadInput as e:
        sys.stderr.write(f"tools/plot: error: {e}\n")
        return 2
    except OSError as e:
        sys.stderr.write(f"tools/plot: error: {e}\n")
        return 1
