#!/usr/bin/env bash
# Runs the libFuzzer targets (built by the fuzz preset, or by packaging/test.sh's asan build), each
# for SECONDS, as many at once as the machine has cores, and prints one line per target:
# executions, seconds, corpus size, result. Exits non-zero when any target found a crash, a leak,
# a timeout or a sanitizer report; the input is kept in WORK/TARGET/artifacts/ (copy it to
# tests/fuzz/regressions/TARGET/ once fixed: the ordinary tests replay it from then on).
#
#   bash tests/fuzz/run.sh [--seconds S] [--build DIR] [TARGET...]
#
# Default: 60 s, every target, the fuzz preset's build (build/fuzz), WORK = build/fuzz/work.
# `--build build/asan` runs the targets that packaging/test.sh builds beside the ASan tests
# (coverage hooks in the readers' libraries only), WORK = build/asan/fuzz-work.
#
# Each target starts from its seeds (tests/fuzz/corpus/TARGET), its regressions and the matching
# folder of tests/bad-inputs; what it finds new is kept in WORK/TARGET/corpus, so a second run
# goes on from where the first stopped.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$root/build/fuzz"
seconds=60
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds)
      [[ "${2:-}" =~ ^[0-9]+$ ]] || { echo "run.sh: --seconds needs a whole number" >&2; exit 2; }
      seconds="$2"; shift 2 ;;
    --build)
      [ -d "${2:-}" ] || { echo "run.sh: --build needs a build folder (got '${2:-}')" >&2; exit 2; }
      build="$(CDPATH='' cd -- "$2" && pwd)"; shift 2 ;;
    -*) echo "run.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
bin="$build/bin"
work="$build/work"
[ "$build" = "$root/build/fuzz" ] || work="$build/fuzz-work"
if [ "${#targets[@]}" -eq 0 ]; then
  # Every target has its seed corpus (tests/fuzz/corpus/TARGET); the build folder also holds other
  # programs named fuzz_* (fuzz_corpus_tests, the ordinary replay of the corpora).
  for d in "$root"/tests/fuzz/corpus/*/; do targets+=("$(basename "$d")"); done
fi
for t in "${targets[@]}"; do
  [ -x "$bin/fuzz_$t" ] || {
    echo "run.sh: no $bin/fuzz_$t (build it: cmake --preset fuzz && cmake --build --preset fuzz," \
      "or a clang build configured with -DLAP_BUILD_FUZZ=ON)" >&2
    exit 2
  }
done

# The bad-input corpus folders that hold the target's format, if any.
bad_inputs_of() {
  case "$1" in
    scenario) echo scenario scenario-yaml ;; mesh_obj) echo obj ;; mesh_stl) echo stl ;; mesh_ply) echo ply ;;
    mesh_off) echo off ;; mesh_gltf|mesh_glb) echo gltf ;; height_image) echo height-map ;;
    keyframes) echo keyframes ;; device_recording) echo lapdev ;;
    session_record|session_recording) echo session ;;  # folders: libFuzzer reads them recursively
  esac
}

run_one() {
  local t="$1" dir="$work/$1"
  rm -rf "$dir/artifacts"
  mkdir -p "$dir/corpus" "$dir/artifacts"
  local seeds=("$root/tests/fuzz/corpus/$t")
  [ -d "$root/tests/fuzz/regressions/$t" ] && seeds+=("$root/tests/fuzz/regressions/$t")
  local bad
  for bad in $(bad_inputs_of "$t"); do seeds+=("$root/tests/bad-inputs/$bad"); done
  # -close_fd_mask=3: the readers' own messages are not printed (libFuzzer's still are).
  set +e
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$bin/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 -close_fd_mask=3 -artifact_prefix="$dir/artifacts/" \
    "$dir/corpus" "${seeds[@]}" > "$dir/log" 2>&1
  echo $? > "$dir/rc"
}
export -f run_one bad_inputs_of
export root bin work seconds
printf '%s\n' "${targets[@]}" | xargs -P "$(nproc)" -I{} bash -c 'run_one "$@"' _ {}

failed=0
printf '%-18s %12s %8s %8s  %s\n' target executions seconds corpus result
for t in "${targets[@]}"; do
  dir="$work/$t"
  runs="$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$dir/log" | grep -o '[0-9]*$' || echo '?')"
  took="$(grep -o 'Done [0-9]* runs in [0-9]* second' "$dir/log" | grep -o 'in [0-9]*' | grep -o '[0-9]*' || echo '?')"
  corpus="$(find "$dir/corpus" -type f | wc -l)"
  if [ "$(cat "$dir/rc")" = "0" ]; then result="clean"; else result="FAILED (exit $(cat "$dir/rc"))"; failed=1; fi
  printf '%-18s %12s %8s %8s  %s\n' "$t" "$runs" "$took" "$corpus" "$result"
done
if [ "$failed" != "0" ]; then
  for t in "${targets[@]}"; do
    if [ "$(cat "$work/$t/rc")" != "0" ]; then
      echo "== fuzz_$t: $(ls "$work/$t/artifacts" 2>/dev/null | tr '\n' ' ')"
      tail -60 "$work/$t/log"
    fi
  done
  exit 1
fi
