#!/usr/bin/env bash
# The suite's time and memory bounds on a busy machine: every test marked `bounded`
# (tests/test_bounded_marks.py keeps the marks complete), run as `make test` runs them
# while HOGS processes (default 8) spin on the CPU. Each bound is CPU time of the process
# tree, a ratio to a reference of the same run, or a generous hang guard, so the run must
# pass as it does on an idle machine, only slower. Not part of the suite: run it by hand
# (tests/load_check.sh [PYTEST ARGS...]) after adding or changing a bound.
set -euo pipefail
cd "$(dirname "$0")/.."
HOGS="${HOGS:-8}"
PYTHON="${PYTHON:-.venv/bin/python}"

hogs=()
stop_hogs() {
  if [ "${#hogs[@]}" -gt 0 ]; then
    kill "${hogs[@]}" 2> /dev/null || true
    wait "${hogs[@]}" 2> /dev/null || true
  fi
}
trap stop_hogs EXIT
for _ in $(seq "$HOGS"); do
  "$PYTHON" -c 'while 1: pass' &
  hogs+=("$!")
done

echo "load_check: $HOGS CPU hogs on $(nproc) cores; pytest -m bounded $*"
start=$(date +%s)
status=0
"$PYTHON" -m pytest -q -n 2 --dist loadfile --no-loadscope-reorder -p no:cacheprovider -m bounded "$@" || status=$?
echo "load_check: exit $status after $(($(date +%s) - start)) s (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
exit "$status"
