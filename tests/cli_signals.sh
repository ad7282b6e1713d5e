#!/usr/bin/env bash
# gmonrt under signals (see `gmonrt --help`, Exit status):
#   SIGTERM from `timeout` and SIGHUP during the render write the image of
#   the samples done and exit 128 + the signal;
#   Ctrl-C (SIGINT) during the kernel build (an empty PoCL cache makes it
#   take seconds) exits at once and leaves an existing output untouched;
#   a second Ctrl-C during the render exits at once, also leaving it.
# usage: cli_signals.sh GMONRT SCENE WORK_DIR   (POCL_CACHE_DIR: a warm cache)
set -uo pipefail
gmonrt=$(realpath "$1") scene=$(realpath "$2")
work="$(realpath "$3")/cli-signals"
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
failures=0
fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}
now_ms() { echo $(($(date +%s%N) / 1000000)); }
# Waits (at most 300 s) for a file to appear; fails if the process ended first.
wait_for() {
  for _ in $(seq 3000); do
    [ -e "$1" ] && return 0
    kill -0 "$2" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}
# An old output that must survive: its bytes are compared afterwards.
make_old_output() {
  printf 'a good image from before\n' >"$1"
  cp "$1" "$1.expected"
}
check_untouched() {
  cmp -s "$1" "$1.expected" || fail "$2: $1 was replaced"
  ls ./*.partial-* >/dev/null 2>&1 && fail "$2: temporary files left: $(ls ./*.partial-*)"
}
render=(--resolution 16x16 --sets 4 --write-sets "$scene")

# Warm-up: the kernels into the cache, then a warm start timed to size the
# time limit below.
"$gmonrt" --quiet --spp 1 --outfile warm.exr "${render[@]}" 2>warm.log || fail "warm-up render: $(cat warm.log)"
start=$(now_ms)
"$gmonrt" --quiet --spp 1 --outfile warm.exr "${render[@]}" 2>warm.log || fail "warm-up render: $(cat warm.log)"
warm_ms=$(($(now_ms) - start))

# SIGTERM from `timeout` mid-render: the image of the samples done, exit 143.
limit=$(((3 * warm_ms + 2999) / 1000)) # seconds
timeout --preserve-status -s TERM "$limit" "$gmonrt" --spp 100000000 --outfile term.exr "${render[@]}" 2>term.log
code=$?
[ "$code" = 143 ] || fail "timeout -s TERM $limit: exit $code, expected 143: $(cat term.log)"
grep -q "interrupted: writing the [1-9][0-9]* samples per pixel done" term.log || fail "TERM: $(cat term.log)"
grep -q "^wrote term.exr and term.png" term.log || fail "TERM: no image written: $(cat term.log)"
# What was written is a valid render of those samples.
"$gmonrt" estimate --quiet --outfile term-estimate.exr term.exr 2>estimate.log ||
  fail "estimate of the interrupted render: $(cat estimate.log)"

# The same SIGTERM delivered twice in quick succession (as `timeout` does:
# to the command, then to its process group; here 20 ms apart, so that the
# first is handled before the second arrives): one interrupt, the image
# written.
# (passes of about a second, as below, so the second arrives mid-pass)
"$gmonrt" --quiet --spp 100000000 --estimators mean --resolution 1024x1024 --checkpoints double \
  --outfile double.exr "$scene" 2>double.log &
pid=$!
wait_for double/spp-000001.exr $pid || fail "double TERM: no first checkpoint: $(cat double.log)"
kill -TERM $pid
sleep 0.02
kill -TERM $pid
wait $pid
code=$?
[ "$code" = 143 ] || fail "TERM twice at once: exit $code, expected 143: $(cat double.log)"
[ -s double.exr ] || fail "TERM twice at once: no image written: $(cat double.log)"

# SIGHUP (a closed terminal) once the first pass is done: exit 129.
"$gmonrt" --quiet --spp 100000000 --checkpoints hup --outfile hup.exr "${render[@]}" 2>hup.log &
pid=$!
wait_for hup/spp-000001.exr $pid || fail "HUP: no first checkpoint: $(cat hup.log)"
kill -HUP $pid
wait $pid
code=$?
[ "$code" = 129 ] || fail "SIGHUP: exit $code, expected 129: $(cat hup.log)"
[ -s hup.exr ] && [ -s hup.png ] || fail "SIGHUP: no image written: $(cat hup.log)"

# Ctrl-C during a cold kernel build: out at once, the old output untouched.
make_old_output build.exr
mkdir empty-cache
POCL_CACHE_DIR="$PWD/empty-cache" "$gmonrt" --spp 4 --outfile build.exr "${render[@]}" 2>build.log &
pid=$!
sleep 1
kill -INT $pid
sent=$(now_ms)
wait $pid
code=$?
took_ms=$(($(now_ms) - sent))
[ "$code" = 130 ] || fail "SIGINT in the build: exit $code, expected 130: $(cat build.log)"
[ "$took_ms" -lt 3000 ] || fail "SIGINT in the build: exited $took_ms ms after the signal"
grep -q "exiting at once" build.log || fail "SIGINT in the build: $(cat build.log)"
check_untouched build.exr "SIGINT in the build"
rm -rf empty-cache

# A second Ctrl-C during the render: out at once, the old output untouched.
# 1024x1024 with the mean only: passes of about a second on a CPU, so the
# second signal comes well before the first pass after it ends.
make_old_output twice.exr
"$gmonrt" --spp 100000000 --estimators mean --resolution 1024x1024 --checkpoints twice --outfile twice.exr \
  "$scene" 2>twice.log &
pid=$!
wait_for twice/spp-000001.exr $pid || fail "second SIGINT: no first checkpoint: $(cat twice.log)"
kill -INT $pid
for _ in $(seq 100); do
  grep -q "finishing the pass" twice.log && break
  sleep 0.05
done
sleep 0.3 # a second interrupt, not the first one delivered twice (within 100 ms)
kill -INT $pid
wait $pid
code=$?
[ "$code" = 130 ] || fail "second SIGINT: exit $code, expected 130: $(cat twice.log)"
grep -q "exiting at once" twice.log || fail "second SIGINT: $(cat twice.log)"
check_untouched twice.exr "second SIGINT"

[ "$failures" = 0 ] && echo "all signal cases passed (warm start $warm_ms ms, time limit $limit s)"
exit $((failures > 0))
