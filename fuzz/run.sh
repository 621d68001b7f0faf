#!/usr/bin/env bash
# Run every fuzz target for SECONDS (default 600), JOBS at a time (default 2),
# from the seeds make_seeds.sh builds (the project's fixtures and the test-data
# folder's real files, into the gitignored corpus-seeds/), the hand-written
# seeds committed in fuzz/seeds/<target>, plus any EXTRA_SEEDS dirs (passed
# through make_seeds.sh), and print one summary line per target from
# libFuzzer's final stats.
#   fuzz/run.sh [SECONDS] [TARGET...]
# Needs cargo-fuzz; on a stable toolchain RUSTC_BOOTSTRAP=1 is set for it.
# Logs: fuzz/logs/<target>.log; crashes: fuzz/artifacts/<target>/.
set -uo pipefail
cd "$(dirname "$0")"
secs=${1:-600}; shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(urdf launch yaml tf_static json rig_toml points graph xacro pyexpr)
jobs=${JOBS:-2}
sanitizer=${SANITIZER:-address}
export RUSTC_BOOTSTRAP=1
mkdir -p logs
./make_seeds.sh corpus-seeds
if [ -n "${EXTRA_SEEDS:-}" ]; then
    ./make_seeds.sh corpus-extra $EXTRA_SEEDS
fi
for t in "${targets[@]}"; do
    mkdir -p "corpus/$t" "artifacts/$t"
    [ -d "seeds/$t" ] && cp -n seeds/$t/* "corpus/$t/" 2>/dev/null
    [ -d "corpus-seeds/$t" ] && cp -n corpus-seeds/$t/* "corpus/$t/" 2>/dev/null
    [ -d "corpus-extra/$t" ] && cp -n corpus-extra/$t/* "corpus/$t/" 2>/dev/null
done
cargo fuzz build -O --sanitizer "$sanitizer" >logs/build.log 2>&1 || { echo "build failed: see fuzz/logs/build.log"; exit 2; }
run_one() {
    local t=$1
    local extra=()
    # Targets named in FORK_TARGETS run in fork mode, so that a known crash does
    # not end the run (none by default: every known crash is fixed).
    case " ${FORK_TARGETS-} " in *" $t "*) extra=(-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1) ;; esac
    cargo fuzz run -O --sanitizer "$sanitizer" "$t" "corpus/$t" -- "${extra[@]}" \
        -max_total_time="$secs" -rss_limit_mb=2048 -timeout=10 -max_len=65536 \
        -print_final_stats=1 -artifact_prefix="artifacts/$t/" >"logs/$t.log" 2>&1
    local rc=$?
    local execs crashes
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "logs/$t.log" | tail -1 | grep -o '[0-9]*$')
    # fork mode prints no final stats: take the last "#N" status line.
    [ -z "$execs" ] && execs=$(grep -o '^#[0-9]*' "logs/$t.log" | tail -1 | tr -d '#')
    crashes=$(ls "artifacts/$t" 2>/dev/null | grep -c -E '^(crash|oom|timeout|leak|slow-unit)-' || true)
    printf '%-10s %5ss  execs=%-10s exit=%-3s artifacts=%s  corpus=%s\n' \
        "$t" "$secs" "${execs:-?}" "$rc" "$crashes" "$(ls corpus/$t | wc -l)"
}
running=0
for t in "${targets[@]}"; do
    run_one "$t" &
    running=$((running + 1))
    if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
done
wait
