#!/usr/bin/env bash
# A reference cache shared by many runs at once (docs/reference.md "A cache on shared
# storage"): identical keys give identical bytes (no time, pid or host in a file); two processes
# drawing the same cache keys at once both finish, and the entries they leave are whole, valid and
# byte-identical to a serial run's, as are both outputs; a reader polling the cache meanwhile never
# sees a partial entry; a damaged entry (truncated, zero-filled: what a crash can leave) is drawn
# again; temporaries in the cache are tidied by host.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/shared_cache
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

REF=(reference fence --frames 2 --width 64 --height 36 --supersample 2 --quiet)

# same_files A B GLOB N: N files matching GLOB in A, each byte-identical to the same name in B
same_files() {
  local a=$1 b=$2 glob=$3 n=$4 f k=0
  for f in "$a"/$glob; do
    [ -f "$f" ] || continue
    cmp -s "$f" "$b/$(basename "$f")" || { echo "  $f differs from $b/$(basename "$f") or one is missing" >&2; return 1; }
    k=$((k + 1))
  done
  [ "$k" -eq "$n" ] || { echo "  $k files $glob in $a, wanted $n" >&2; return 1; }
}
no_temps() { [ -z "$(find "$@" -name '*.tmp.*')" ]; }

# ---- identical keys, identical bytes: two caches drawn one after the other, apart
"$BIN" "${REF[@]}" --cache "$T/serial" --out "$T/s1" >/dev/null 2>"$T/err.txt"
check "serial run exits 0" test $? -eq 0
"$BIN" "${REF[@]}" --cache "$T/serial2" --out "$T/s2" >/dev/null 2>&1
check "the same entries drawn twice are byte-identical" same_files "$T/serial" "$T/serial2" 'ref-*.exr' 2
check "the same frames drawn twice are byte-identical" same_files "$T/s1" "$T/s2" 'reference.*.exr' 2

# ---- two processes, the same keys, one cache, at once. Each round starts both together on an
# empty cache; a reader compares every entry it finds with the serial one while they run. A round
# races when both processes drew (and wrote) the same frame: usual, not certain (it depends on
# how their starts overlap), so rounds go on until 3 raced, at most 10.
rounds=0 raced=0
while [ $raced -lt 3 ] && [ $rounds -lt 10 ]; do
  rounds=$((rounds + 1)) r=$rounds
  C="$T/c$r"; mkdir -p "$C"
  ( while :; do
      for f in "$C"/ref-*.exr; do
        [ -e "$f" ] || continue
        cmp -s "$f" "$T/serial/$(basename "$f")" || echo "$f" >>"$T/partial.txt"
      done
      [ -e "$T/stop" ] && break
    done ) &
  reader=$!
  "$BIN" "${REF[@]}" --cache "$C" --out "$T/o$r-1" >"$T/o$r-1.txt" 2>&1 & p1=$!
  "$BIN" "${REF[@]}" --cache "$C" --out "$T/o$r-2" >"$T/o$r-2.txt" 2>&1 & p2=$!
  wait $p1; rc1=$?; wait $p2; rc2=$?
  : >"$T/stop"; wait $reader; rm -f "$T/stop"
  check "round $r: both processes exit 0" test $rc1 -eq 0 -a $rc2 -eq 0
  check "round $r: the cache holds 2 entries, byte-identical to the serial run's" same_files "$C" "$T/serial" 'ref-*.exr' 2
  check "round $r: both outputs byte-identical to each other" same_files "$T/o$r-1" "$T/o$r-2" 'reference.*.exr' 2
  check "round $r: and to the serial run's" same_files "$T/o$r-1" "$T/s1" 'reference.*.exr' 2
  check "round $r: no temporary file left" no_temps "$C" "$T/o$r-1" "$T/o$r-2"
  d1=$(sed -n 's/^ *\([0-9]*\) drawn, .*/\1/p' "$T/o$r-1.txt") d2=$(sed -n 's/^ *\([0-9]*\) drawn, .*/\1/p' "$T/o$r-2.txt")
  [ $((${d1:-0} + ${d2:-0})) -gt 2 ] && raced=$((raced + 1))
done
check "a reader never saw an entry other than the whole, serial one" test ! -s "$T/partial.txt"
echo "note: in $raced of $rounds rounds both processes drew and wrote the same frame at once" >&2
# The entries are valid to fovsim too: key, size, channels and checksum (cache_load).
"$BIN" "${REF[@]}" --cache "$T/c1" --out "$T/again" >"$T/again.txt" 2>&1
check "a later run takes both frames from the shared cache" grep -q '0 drawn, 2 from the cache' "$T/again.txt"

# ---- damaged entries are drawn again and replaced by whole ones. rename(2) never shows a partial
# file under the entry's name, but a crash of the machine (or the file server) after the rename
# and before the data reached the disk can leave one truncated, empty or zero-filled; so can a copy.
entries=("$T/c1"/ref-*.exr)
e0=${entries[0]} e1=${entries[1]}
size0=$(stat -c %s "$e0") size1=$(stat -c %s "$e1")
truncate -s $((size0 / 2)) "$e0"
dd if=/dev/zero of="$e1" bs=1 seek=$((size1 / 2)) count=$((size1 - size1 / 2)) conv=notrunc status=none
check "damaged: the zero-filled entry keeps its size" test "$(stat -c %s "$e1")" -eq "$size1"
"$BIN" "${REF[@]}" --cache "$T/c1" --out "$T/d1" >"$T/d1.txt" 2>&1
check "half-written entries: the run exits 0 and draws both again" grep -q '2 drawn, 0 from the cache' "$T/d1.txt"
check "half-written entries: replaced by the whole ones" same_files "$T/c1" "$T/serial" 'ref-*.exr' 2
check "half-written entries: the frames are the serial run's" same_files "$T/d1" "$T/s1" 'reference.*.exr' 2
: >"$e0"
head -c "$size1" /dev/zero >"$e1"
"$BIN" "${REF[@]}" --cache "$T/c1" --out "$T/d2" >"$T/d2.txt" 2>&1
check "empty and all-zero entries: drawn again" grep -q '2 drawn, 0 from the cache' "$T/d2.txt"
check "empty and all-zero entries: replaced by the whole ones" same_files "$T/c1" "$T/serial" 'ref-*.exr' 2

# ---- temporaries in the cache: this host's of a dead process are removed when a run opens the
# cache; another host's are kept (a run there may be about to rename it) until a day old.
host=$(uname -n | tr -c 'A-Za-z0-9\n-' '-')
if [ ${#host} -le 32 ]; then
  other=x${host:1}; [ "$other" != "$host" ] || other=y${host:1}
  sleep 0 & dead=$!; wait $dead
  k=$(basename "$e0")
  : >"$T/c1/.$k.tmp.$host.$dead.0"; : >"$T/c1/.$k.tmp.$other.$dead.1"; : >"$T/c1/.$k.tmp.$other.$dead.2"
  touch -d '2 days ago' "$T/c1/.$k.tmp.$other.$dead.2"
  "$BIN" "${REF[@]}" --cache "$T/c1" --out "$T/d3" >/dev/null 2>&1
  check "cache: this host's temporary of a dead process removed" test ! -e "$T/c1/.$k.tmp.$host.$dead.0"
  check "cache: another host's temporary kept" test -e "$T/c1/.$k.tmp.$other.$dead.1"
  check "cache: another host's temporary two days old removed" test ! -e "$T/c1/.$k.tmp.$other.$dead.2"
else
  echo "note: host name over 32 characters; the host-named temporary checks did not run" >&2
fi

# One rule for an entry the cache cannot hold (docs/reference.md "Cache"): a directory at an entry's path and a cache
# folder that cannot be made (here under a regular file, which stops root too) both stop the run
# with one line, exit 6, and the directory (someone's files) is kept. Before, the directory was
# bypassed with a warning (exit 0).
echo x >"$T/afile"
expect_exit "cache: a folder that cannot be made: exit 6, one line" 6 "$BIN" "${REF[@]}" --cache "$T/afile/cache" --out "$T/d4"
mkdir -p "$T/c5" && "$BIN" "${REF[@]}" --cache "$T/c5" --out "$T/d5" >/dev/null 2>&1
e5=$(ls "$T/c5"/ref-*.exr | head -1)
rm -f "$e5" && mkdir "$e5" && : >"$e5/someones_file"
expect_exit "cache: a directory at an entry's path: exit 6, one line" 6 "$BIN" "${REF[@]}" --cache "$T/c5" --out "$T/d6"
check "cache: ... naming it" grep -q "is a directory where the reference cache keeps an entry" "$T/err.txt"
check "cache: ... and the directory and its file are kept" test -f "$e5/someones_file"

summary
