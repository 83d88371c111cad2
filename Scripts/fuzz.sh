#!/usr/bin/env bash
# Long fuzz run (default 30 minutes, all cores) of the filter in the sanitizer build; failing
# cases go to build-asan/Testing/Temporary/fuzz-long/ with their replay commands.
# Usage: Scripts/fuzz.sh [minutes] [more Testing/Fuzz/fuzz_filter.py arguments, e.g. --seed 7]
set -euo pipefail
cd "$(dirname "$0")/.."
minutes="${1:-30}"
shift || true

if [ ! -f build-asan/TetDSRTestEnvironment.cmake ]; then
  echo "No sanitizer build: run Scripts/sanitize.sh first." >&2
  exit 2
fi
cmake --build build-asan # incremental
# The tests' environment (sanitizer runtimes and options), as TETDSR_SANITIZE wrote it.
eval "$(sed -n 's/^set(ENV{\(.*\)} \[==\[\(.*\)\]==\])$/export \1="\2"/p' build-asan/TetDSRTestEnvironment.cmake)"
export PYTHONPATH="$PWD/build-asan/lib/python3/dist-packages"
exec /usr/bin/python3 Testing/Fuzz/fuzz_filter.py --minutes "$minutes" --jobs "$(nproc)" \
  --timeout 120 --out build-asan/Testing/Temporary/fuzz-long "$@"
