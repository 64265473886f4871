#!/usr/bin/env bash
# Seeds the corpora from the fixtures (idempotent) and runs every fuzz target for N seconds.
#
#   fuzz/run.sh [SECONDS] [TARGET...]      # default: 60 s, every target
#
# Stable toolchain: RUSTC_BOOTSTRAP=1 lets stable rustc accept the -Z flags cargo-fuzz passes.
# Needs `cargo install cargo-fuzz`. A crash, OOM (>1 GB RSS) or hang (>5 s per input) stops
# the target and leaves the input in fuzz/artifacts/<target>/; see tests/fuzz_regressions.rs.
set -euo pipefail

SECONDS_PER_TARGET="${1:-60}"
shift || true
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(dirname "$HERE")"
SHARED="${KANSEI_SHARED_HID:-$ROOT/fixtures/hid/oracle}"
TARGETS=("$@")
if [ ${#TARGETS[@]} -eq 0 ]; then
    TARGETS=(hid_descriptor hid_layout hid_report hid_recorder evemu inkml stroke_json fit_stroke)
fi
export RUSTC_BOOTSTRAP=1

# A hid-recorder file without comments, cut to its header and first N `E:` lines: a small seed.
head_recording() { awk -v n="$2" '/^#/ { next } /^E:/ { if (++e > n) exit } { print }' "$1"; }

seed() {
    local c="$HERE/corpus"
    mkdir -p "$c"/{hid_descriptor,hid_layout,hid_report,hid_recorder,evemu,inkml,stroke_json,fit_stroke}
    # fit_stroke: a few byte strings of small moves (a line, a reversal, a jiggle).
    printf "\x00\x99\x88\x99\x88\x99\x88\x77\x88\x77\x88" > "$c/fit_stroke/seed-reversal"
    printf "\x00\x98\x89\x98\x89\x98\x89\x98" > "$c/fit_stroke/seed-jiggle"
    # Turning mode (head 0xf0 and up): a circle drawn past its start, a spiral.
    printf "\xf0\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04\x0b\x04" > "$c/fit_stroke/seed-circle-past-start"
    printf "\xf1\x0c\x01\x0c\x02\x0c\x03\x0c\x04\x0c\x05\x0c\x06\x0c\x07\x0c\x08\x0c\x09\x0c\x0a\x0c\x0b\x0c\x0c\x0c\x0d\x0c\x0e\x0c\x0f" > "$c/fit_stroke/seed-spiral"
    printf "\x01\x99\x99\x99\x99\x9a\x98\x9a\x98\x9b\x97" > "$c/fit_stroke/seed-curve"
    local recs=("$ROOT"/fixtures/hid/*.hid)
    [ -d "$SHARED" ] && recs+=("$SHARED"/*.hid)
    local i=0
    for f in "${recs[@]}"; do
        i=$((i + 1))
        grep -m1 '^R:' "$f" | cut -d' ' -f3- | xxd -r -p > "$c/hid_descriptor/seed-$i"
        head_recording "$f" 40 > "$c/hid_recorder/seed-$i"
        # hid_layout: <u16 LE descriptor length><descriptor> then <length byte><report> x 40.
        head_recording "$f" 40 | awk '
            /^R:/ { n = $2; printf "%02x%02x", n % 256, int(n / 256); for (k = 3; k <= NF; k++) printf "%s", $k }
            /^E:/ { printf "%02x", $3; for (k = 4; k <= NF; k++) printf "%s", $k }' |
            xxd -r -p > "$c/hid_layout/seed-$i"
        # Distinct report shapes of the recording, as raw bytes.
        grep '^E:' "$f" | cut -d' ' -f4- | awk '!seen[$1 NF]++' | head -n 20 | {
            local j=0
            while read -r line; do
                j=$((j + 1))
                echo "$line" | xxd -r -p > "$c/hid_report/seed-$i-$j"
            done
        }
    done
    cp "$ROOT"/fixtures/evemu/*.evemu "$c/evemu/"
    cp "$ROOT"/fixtures/inkml/*.inkml "$c/inkml/"
    cp "$ROOT"/fixtures/strokes/*.json "$c/stroke_json/"
}

seed
cd "$HERE"
for t in "${TARGETS[@]}"; do
    echo "=== $t: ${SECONDS_PER_TARGET}s"
    cargo fuzz run "$t" "corpus/$t" -- \
        -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb=1024 -timeout=5 -print_final_stats=1
done
