#!/usr/bin/env bash
# Installs what the FuseSoC core tests (hdl/tests/fusesoc.rs) need beyond .ci/run's EDA tools:
# FuseSoC and its backend library edalize, at the tested versions (PyPI). Called by .ci/run
# before the test suite; about 5 s on a fresh machine.
set -euo pipefail
python3 -c "import fusesoc, edalize" 2>/dev/null && command -v fusesoc >/dev/null 2>&1 ||
  python3 -m pip install -q fusesoc==2.4.7 edalize==0.6.8
