#!/usr/bin/env bash
# Installs the built pushpred into a scratch prefix and builds and runs a consumer project against it.
set -eu
build=$1
source_dir=$2
data=$3
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix/usr" >/dev/null
cmake -S "$source_dir/tests/install/consumer" -B "$prefix/consumer-build" -DCMAKE_PREFIX_PATH="$prefix/usr" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$prefix/consumer-build" >/dev/null
file=$(ls "$data"/abs/*shape=hex*.h5 | head -1)
LD_LIBRARY_PATH="$prefix/usr/lib:$prefix/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
  "$prefix/consumer-build/consumer" "$file"
echo "1 passed, 0 failed"
