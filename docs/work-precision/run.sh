#!/usr/bin/env bash
# Regenerates docs/work-precision.md: bgdsl's stiff methods (the ignored test
# bgdsl-runtime/tests/stiff_work_precision.rs, release build), scipy's Radau, BDF and
# LSODA and SUNDIALS' CVODE (others.py, through scikit-sundae, whose wheels bundle
# SUNDIALS) on the Bari test-set problems at rtol 1e-3 ... 1e-10, and bgdsl alone on the
# flagship (models/tests/flagship_work_precision.rs). Takes about ten
# minutes on two cores (most of it scipy at tight tolerances).
#
# Usage: bash docs/work-precision/run.sh          (from anywhere in the repository)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
cd "$root"
python3 -c 'import scipy, sksundae' 2>/dev/null || python3 -m pip install --quiet scipy scikit-sundae
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
nice -n 10 cargo test --release -p bgdsl-runtime --test stiff_work_precision -- \
    --ignored --nocapture | grep '^WP' > "$tmp/bgdsl.tsv"
# The flagship (a release build of the models crate: a few minutes the first time).
nice -n 10 cargo test --release -p models --test flagship_work_precision -- \
    --ignored --nocapture | grep '^WP' >> "$tmp/bgdsl.tsv"
(cd "$here" && nice -n 10 python3 others.py) > "$tmp/others.tsv"
(cd "$here" && python3 report.py "$tmp/bgdsl.tsv" before-issue-15.tsv "$tmp/others.tsv") \
    > docs/work-precision.md
echo "wrote docs/work-precision.md"
