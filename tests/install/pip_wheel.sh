#!/usr/bin/env bash
# `pip wheel --no-build-isolation` of a copy of the package's sources (pyproject.toml, setup.py), taking the module
# from this build (PUSHPRED_CMAKE_BUILD_DIR, so that the test does not build the library a second time), installed
# with `pip install --target`; then the module's tests run from that installed copy, which must load the
# libpushpred inside the wheel, not the build's.
set -eu
source "$(dirname "${BASH_SOURCE[0]}")/../support/skip_without_real_data.sh"
build=$1
source_dir=$2
data=$3
python=$4
executable=$5
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
# The package's sources only: pip builds in the source folder, which must not be the checkout.
mkdir -p "$scratch/src/docs"
cp -r "$source_dir/pyproject.toml" "$source_dir/setup.py" "$source_dir/CMakeLists.txt" "$source_dir/python" \
  "$scratch/src/"
cp "$source_dir/docs/python.md" "$scratch/src/docs/"
PUSHPRED_CMAKE_BUILD_DIR="$build" "$python" -m pip wheel --no-build-isolation --no-deps --no-index \
  -w "$scratch/wheels" "$scratch/src" >"$scratch/wheel.log" 2>&1 || { cat "$scratch/wheel.log"; exit 1; }
wheel=$(ls "$scratch"/wheels/pushpred-*.whl)
echo "built $(basename "$wheel")"
"$python" -m pip install --no-deps --no-index --target "$scratch/site" "$wheel" >"$scratch/install.log" 2>&1 ||
  { cat "$scratch/install.log"; exit 1; }
cd "$scratch"
where=$(PYTHONPATH="$scratch/site" "$python" -c "import pushpred
print(pushpred.__file__)
print(*[l.split()[-1] for l in open('/proc/self/maps') if 'libpushpred' in l][:1])")
echo "$where"
if ! grep -q "^$scratch/site/pushpred/__init__.py$" <<<"$where" ||
  ! grep -q "^$scratch/site/pushpred/libpushpred.so" <<<"$where"; then
  echo "FAIL: the installed wheel's module or its library was not the one loaded"
  exit 1
fi
# A wrong interpreter is named: without site-packages (-S) numpy cannot be imported, and the import says for which
# interpreter the module was built.
if PYTHONPATH="$scratch/site" "$python" -S -c "import pushpred" 2>"$scratch/err"; then
  echo "FAIL: the module imported without numpy"
  exit 1
fi
if ! grep -q "pushpred was built for $python (Python " "$scratch/err"; then
  echo "FAIL: the import error does not name the interpreter:"
  cat "$scratch/err"
  exit 1
fi
PYTHONPATH="$scratch/site" PUSHPRED_DATA="$data" PUSHPRED_EXECUTABLE="$executable" PUSHPRED_SOURCE_DIR="$source_dir" \
  PYTHONDONTWRITEBYTECODE=1 "$python" -m pytest -q -p no:cacheprovider --rootdir="$source_dir/tests/python" \
  "$source_dir/tests/python/test_reading.py" "$source_dir/tests/python/test_python_api.py"
