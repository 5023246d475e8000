#!/usr/bin/env bash
# Runs each libFuzzer target for a fixed time (`make fuzz`). Usage:
#   tests/fuzz/run_fuzzers.sh BUILD_DIR SECONDS TARGET...
# Each target starts from a scratch copy of tests/fuzz/corpus/<target> (the committed
# corpus never grows). Any crash, sanitizer report, uncaught exception, timeout (10 s
# per input) or use of more than 2 GiB fails the run; the input that did it is kept
# under BUILD_DIR/fuzz-findings/<target>/ and the log under BUILD_DIR/fuzz-logs/.
set -uo pipefail
build=$1 seconds=$2
shift 2
source_dir=$(cd "$(dirname "$0")" && pwd)
findings=$build/fuzz-findings logs=$build/fuzz-logs
mkdir -p "$findings" "$logs"
# The targets write their input to a file per run (the readers take paths): keep the
# scratch files in memory when the machine has /dev/shm. The targets' own folders go
# under $scratch/tmp too, so everything is removed at the end.
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
scratch=$(mktemp -d "${TMPDIR:-/tmp}/lancer-fuzz.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/tmp"
export TMPDIR=$scratch/tmp

failed=()
for target in "$@"; do
  binary=$build/tests/fuzz/${target}_fuzz
  if [ ! -x "$binary" ]; then
    echo "fuzz: $binary is missing (build it with LANCER_FUZZ=ON and clang)" >&2
    failed+=("$target")
    continue
  fi
  rm -rf "${findings:?}/$target"
  corpus=$scratch/corpus/$target
  mkdir -p "$corpus" "$findings/$target"
  cp "$source_dir/corpus/$target/"* "$corpus/"
  log=$logs/$target.log
  echo "fuzz: $target for ${seconds} s (log: $log)"
  start=$SECONDS
  "$binary" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$findings/$target/" "$corpus" >"$log" 2>&1
  status=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  if [ $status -ne 0 ]; then
    echo "fuzz: $target FAILED (exit $status after $((SECONDS - start)) s); the end of its log:" >&2
    grep -v '^"' "$log" | tail -n 60 >&2
    ls -l "$findings/$target" >&2
    failed+=("$target")
  else
    echo "fuzz: $target clean: ${runs:-?} inputs in $((SECONDS - start)) s"
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: findings in: ${failed[*]} (reproduce: BUILD_DIR/tests/fuzz/<target>_fuzz <input file>)" >&2
  exit 1
fi
