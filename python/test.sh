#!/usr/bin/env bash
# The Python module's tests: builds the module into a virtualenv
# (target/py-venv, reused, with Open CASCADE from cadquery-ocp) and runs
# pytest and the tour example.
#   bash python/test.sh
# FAIRSURF_PY_PROFILE=release builds it as `pip install ./python` does; the
# default (dev) reuses the workspace's dev build, as CI does after cargo test.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/py-venv
# cadquery-ocp: Open CASCADE for fairsurf.occ and its tests; dask.distributed
# for the cluster test and example.
if ! "$venv/bin/python" -c "import maturin, numpy, pytest, OCP, distributed" >/dev/null 2>&1; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --disable-pip-version-check maturin numpy pytest \
    cadquery-ocp "dask[distributed]"
fi
profile=${FAIRSURF_PY_PROFILE:-dev}
echo "-- build the module ($profile) [${SECONDS} s]"
PATH="$PWD/$venv/bin:$PATH" MATURIN_PEP517_ARGS="--profile $profile" \
  "$venv/bin/pip" install --quiet --disable-pip-version-check --no-build-isolation \
  --force-reinstall --no-deps ./python
echo "-- pytest [${SECONDS} s]"
"$venv/bin/python" -m pytest -q python/tests
echo "-- the examples [${SECONDS} s]"
"$venv/bin/python" python/examples/tour.py "target/py-tour"
"$venv/bin/python" python/examples/dask_sweep.py
echo "-- done [${SECONDS} s]"
