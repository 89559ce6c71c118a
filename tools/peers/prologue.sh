# Shared by tools/peers/bench, compare and growth (sourced, not run): the repository and the build
# (tools/setup.sh), the peers' directory, the command line, the checks for the peers' files and
# binaries, and the figures they read: the step loop's time from a LIGGGHTS or LAMMPS log, and
# bagdem bench's by column name from its CSV (--format csv).
set -euo pipefail
PEERS_TOOLS="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$PEERS_TOOLS/../setup.sh"
TOOL="tools/peers/$(basename "$0")"
PEERS="${PEERS:-$ROOT/../shared/peers}"
PYTHON=/usr/bin/python3

# fail MESSAGE: bad input or something missing: the message on stderr, exit code 2.
fail() { echo "$TOOL: $*" >&2; exit 2; }

# usage: the script's header comment, from its second line to the first line that is not a comment.
usage() { sed -n '2,/^[^#]/{/^#/s/^# \{0,1\}//p}' "$0"; }

# parse_options SPEC ARGS...: SPEC lists the options as "--name:VAR" (takes a value, put in VAR)
# or "--name:VAR=VALUE" (a flag: sets VAR to VALUE); --help (or -h) prints usage and exits 0.
parse_options() {
  local spec="$1" item allowed="" matched
  shift
  for item in $spec; do allowed+="${allowed:+, }${item%%:*}"; done
  while [ $# -gt 0 ]; do
    if [ "$1" = --help ] || [ "$1" = -h ]; then usage; exit 0; fi
    matched=0
    for item in $spec; do
      [ "$1" = "${item%%:*}" ] || continue
      matched=1 item="${item#*:}"
      if [[ "$item" == *=* ]]; then
        printf -v "${item%%=*}" '%s' "${item#*=}"; shift
      else
        [ $# -ge 2 ] || fail "$1 needs a value"
        printf -v "$item" '%s' "$2"; shift 2
      fi
      break
    done
    [ "$matched" = 1 ] || fail "unknown option '$1' (allowed: $allowed, --help)"
  done
}

# need_peers_file PATH: PATH (relative to the peers' directory) must be there.
need_peers_file() { [ -f "$PEERS/$1" ] || fail "no $PEERS/$1 (set PEERS=...)"; }

# need_command COMMAND PACKAGES: COMMAND must be on PATH (PACKAGES: the Debian packages that have it).
need_command() { command -v "$1" >/dev/null || fail "$1 not found; run: apt-get install -y $2"; }

# scratch: a temporary directory in $work, removed when the script exits.
scratch() { work=$(mktemp -d); trap 'rm -rf "$work"' EXIT; }

# scaled_steps BASE SCALE: BASE x SCALE steps, at least 100.
scaled_steps() { "$PYTHON" -c "print(max(100, int($1 * $2)))"; }

# loop_seconds LOG: the wall time of the step loop of a LIGGGHTS or LAMMPS log ("Loop time of").
loop_seconds() { grep -m1 '^Loop time of' "$1" | awk '{print $4}'; }

# ns_per_step SECONDS STEPS N DIGITS: wall time per particle-step in ns, with DIGITS decimals.
ns_per_step() { "$PYTHON" -c "print(f'{$1 / ($2 * $3) * 1e9:.$4f}')"; }

# bench_ns NAME=VALUE... -- BENCH_OPTIONS...: runs `bagdem bench --format csv BENCH_OPTIONS` and
# prints the ns per particle-step (the column ns_per_particle_step) of the one row where each
# column NAME holds VALUE (tools/peers/bench_csv.py). bagdem's stderr is shown only if it fails.
bench_ns() {
  local where=() out rc=0
  while [ "$1" != -- ]; do where+=("$1"); shift; done
  shift
  out=$(mktemp)
  "$BUILD/bagdem" bench --format csv "$@" > "$out" 2> "$out.err" || { cat "$out.err" >&2; rc=1; }
  [ "$rc" != 0 ] || "$PYTHON" "$PEERS_TOOLS/bench_csv.py" ns_per_particle_step "${where[@]}" < "$out" || rc=$?
  rm -f "$out" "$out.err"
  return "$rc"
}
