#!/usr/bin/env bash
# Runs every fuzz target for SECONDS (default 60) each, on stable Rust through
# RUSTC_BOOTSTRAP (cargo-fuzz needs nightly flags). No sanitizer: the crates
# forbid unsafe code, so panics (incl. overflow checks) are what is hunted.
# New inputs go to a scratch corpus; only crashes land in artifacts/.
set -euo pipefail
cd "$(dirname "$0")"
secs=${1:-60}
scratch=${FUZZ_SCRATCH:-/tmp/trigbody-fuzz-corpus}

for t in obj ply stl xyz tbm model; do
  mkdir -p "$scratch/$t"
  dict=()
  [ -f "dict/$t.dict" ] && dict=(-dict="dict/$t.dict")
  RUSTC_BOOTSTRAP=1 cargo fuzz run -s none "$t" "$scratch/$t" "corpus/$t" -- \
    -max_total_time="$secs" -max_len=4096 "${dict[@]}" 2>&1 | tail -4
done
