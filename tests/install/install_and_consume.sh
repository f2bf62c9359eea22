#!/usr/bin/env bash
# Installs the built pushpred into a scratch prefix and builds and runs a consumer project against it.
set -eu
source "$(dirname "${BASH_SOURCE[0]}")/../support/skip_without_real_data.sh"
build=$1
source_dir=$2
data=$3
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix/usr" >/dev/null
# The installed program starts from the prefix alone: its RUNPATH finds libpushpred ($ORIGIN/../lib), with no
# LD_LIBRARY_PATH.
if ! version=$(env -u LD_LIBRARY_PATH "$prefix/usr/bin/pushpred" --version 2>&1); then
  echo "FAIL: the installed pushpred does not start: $version"
  exit 1
fi
if ! grep -Eq '^pushpred [0-9]+\.[0-9]+\.[0-9]+' <<<"$version"; then
  echo "FAIL: the installed pushpred --version printed: $version"
  exit 1
fi
echo "installed program: $version"
file=$(ls "$data"/abs/*shape=hex*.h5 | head -1)
if ! env -u LD_LIBRARY_PATH "$prefix/usr/bin/pushpred" inspect --jobs 1 "$file" >/dev/null; then
  echo "FAIL: the installed pushpred could not inspect $file"
  exit 1
fi
passed=2
# A C++-only consumer project (project(... LANGUAGES CXX)) finds the package and links the library; the consumer
# finds libpushpred through the RUNPATH CMake gives it, again without LD_LIBRARY_PATH.
if ! log=$(cmake -S "$source_dir/tests/install/consumer" -B "$prefix/consumer-build" \
  -DCMAKE_PREFIX_PATH="$prefix/usr" -DCMAKE_BUILD_TYPE=Release 2>&1); then
  echo "FAIL: find_package(pushpred) failed in a C++-only project:"
  echo "$log"
  exit 1
fi
cmake --build "$prefix/consumer-build" >/dev/null
# The consumer's exit status is the check (it exits non-zero on a short read), its output only the evidence; a
# failing step ends the script (set -e) and so the test, which ctest judges by the exit status.
if ! output=$(env -u LD_LIBRARY_PATH "$prefix/consumer-build/consumer" "$file"); then
  echo "FAIL: the installed consumer exited non-zero: $output"
  exit 1
fi
echo "$output"
if ! grep -Eq '^pushpred [0-9.]+ read [0-9]+ samples of hex$' <<<"$output"; then
  echo "FAIL: the consumer did not report reading the hex push"
  exit 1
fi
passed=$((passed + 1))
# The C++ examples build on their own against the installed package.
cmake -S "$source_dir/examples/cpp" -B "$prefix/examples-build" -DCMAKE_PREFIX_PATH="$prefix/usr" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$prefix/examples-build" >/dev/null
passed=$((passed + 1))
# The Python module, when built, is installed beside the library and finds it without LD_LIBRARY_PATH.
python=${4:-}
if [ -n "$python" ]; then
  module_dir=$(dirname "$(find "$prefix/usr" -name '__init__.py' -path '*/pushpred/*' | head -1)")
  output=$(PYTHONPATH="$(dirname "$module_dir")" "$python" -c "import sys, pushpred; p = pushpred.load_push(sys.argv[1]); \
print('python: pushpred', pushpred.__version__, 'read', len(p), 'samples of', p.shape['name'])" "$file")
  echo "$output"
  if ! grep -Eq '^python: pushpred [0-9.]+ read [0-9]+ samples of hex$' <<<"$output"; then
    echo "FAIL: the installed Python module did not read the hex push"
    exit 1
  fi
  passed=$((passed + 1))
fi
echo "$passed passed, 0 failed"
