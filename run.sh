#!/usr/bin/env bash
# Set-up and entry points. On a fresh machine with Python 3.11:
#   ./run.sh demo   creates .venv, installs the package, runs the main job into out/
#   ./run.sh test   creates .venv if needed, runs the test suite (or the tests named after it):
#                   every test but the studies, on two pytest-xdist workers, a file to each,
#                   the longest first (tests/conftest.py; the ROS tests mostly wait)
#   ./run.sh study  the studies: acceptance tests at full size (whole diagnoses, a fleet on a
#                   local cluster, minutes of the monitor beside a loop)
#   ./run.sh bench  runs the benchmarks in benchmarks/ and prints their figures
set -euo pipefail
cd "$(dirname "$0")"
venv=${PNEUMATIC_SERVO_VENV:-.venv}
stamp="$venv/.installed"
if [ ! -f "$stamp" ] || [ setup.py -nt "$stamp" ]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --disable-pip-version-check -e '.[ros,fast,fleet,test]'
  touch "$stamp"
fi
export ROS_AUTOMATIC_DISCOVERY_RANGE=${ROS_AUTOMATIC_DISCOVERY_RANGE:-LOCALHOST}
verb=${1:-demo}
shift || true
case "$verb" in
  demo)  exec "$venv/bin/pneumatic-servo" demo --out out "$@" ;;
  test|study)
         tier=$([ "$verb" = study ] && echo study || echo 'not study')
         [ $# -gt 0 ] || set -- tests -m "$tier" -n "${PNEUMATIC_SERVO_TEST_WORKERS:-2}" \
           --dist loadfile --no-loadscope-reorder --timeout 1800
         exec "$venv/bin/python" -m pytest -q "$@" ;;
  bench) for b in benchmarks/bench_*.py; do echo "== $b"; "$venv/bin/python" "$b" "$@"; done ;;
  *)     exec "$venv/bin/pneumatic-servo" "$verb" "$@" ;;
esac
