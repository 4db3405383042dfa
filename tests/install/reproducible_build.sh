#!/bin/sh
# Two builds of one commit in different folders give identical installed
# binaries: copies the tracked files of the tree at SRC (default: this
# checkout) into two folders of different names and depths, configures each
# as the release preset does (RelWithDebInfo: the debug info is where folder
# names would hide) with the command-line tool only, builds it without ccache
# (a cache hit would hide a difference), installs both and compares every
# installed binary byte for byte. About twice a cold build of the library
# (10-15 minutes on 2 cores), so it is not part of ./dev.sh test: run it with
# ./dev.sh repro.
#   tests/install/reproducible_build.sh [SRC] [WORK]
set -eu
src=$(cd "${1:-$(dirname "$0")/../..}" && pwd)
work=${2:-${TMPDIR:-/tmp}/cmkit-repro}
jobs=${CMKIT_BUILD_JOBS:-2}
rm -rf "$work"
mkdir -p "$work/a" "$work/second/folder"
# One snapshot of the tree for both builds (the tree may change while the
# first one builds).
(cd "$src" && git ls-files -z | xargs -0 tar cf -) >"$work/tree.tar"
for dest in "$work/a/cmkit" "$work/second/folder/cmkit-copy"; do
  mkdir -p "$dest"
  (cd "$dest" && tar xf "$work/tree.tar")
  echo "== building in $dest"
  CCACHE_DISABLE=1 cmake -S "$dest" -B "$dest/build/release" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMKIT_BUILD_TESTS=OFF -DCMKIT_BUILD_BENCH=OFF -DCMKIT_BUILD_FUZZ=OFF -DCMKIT_BUILD_EXAMPLES=OFF \
    -DCMKIT_PYTHON=OFF >/dev/null
  CCACHE_DISABLE=1 cmake --build "$dest/build/release" -j "$jobs" >/dev/null
  cmake --install "$dest/build/release" --prefix "$dest/prefix" >/dev/null
done
a="$work/a/cmkit/prefix"
b="$work/second/folder/cmkit-copy/prefix"
status=0
compared=0
for f in $(cd "$a" && find . -type f | sort); do
  if [ ! -f "$b/$f" ]; then
    echo "only in the first install: $f"; status=1; continue
  fi
  compared=$((compared + 1))
  cmp -s "$a/$f" "$b/$f" || { echo "differs: $f"; status=1; }
done
[ "$(cd "$a" && find . -type f | wc -l)" = "$(cd "$b" && find . -type f | wc -l)" ] || { echo "the installs hold different files"; status=1; }
for f in bin/cmkit lib/libcmkit.a; do
  if grep -c -a -F -e "$work" "$a/$f" >/dev/null; then echo "$f names its build folder"; status=1; fi
done
if [ "$status" = 0 ]; then
  echo "reproducible: $compared installed files identical ($(sha256sum "$a/bin/cmkit" | cut -c1-16) bin/cmkit)"
fi
exit "$status"
