# Sourced by the CLI tests: a scratch folder removed on exit, check helpers that count and print "N passed,
# M failed" at the end, and where the tests find their real pushes (in $data, the data folder, when the test has
# one).
source "$(dirname "${BASH_SOURCE[0]}")/../support/skip_without_real_data.sh"
passed=0
failed=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# expect_exit CODE DESCRIPTION -- COMMAND...: runs COMMAND, keeps its output in $tmp/out and $tmp/err.
expect_exit() {
  local want=$1 what=$2
  shift 3
  "$@" >"$tmp/out" 2>"$tmp/err"
  local got=$?
  if [ "$got" -eq "$want" ]; then passed=$((passed + 1)); else
    failed=$((failed + 1)); echo "FAIL: $what: exit $got, expected $want"; sed 's/^/  err: /' "$tmp/err" | head -5
  fi
}

# expect_in FILE PATTERN DESCRIPTION: FILE contains the fixed string PATTERN.
expect_in() {
  if grep -qF -- "$2" "$1"; then passed=$((passed + 1)); else
    failed=$((failed + 1)); echo "FAIL: $3: '$2' not in $(basename "$1")"; head -5 "$1" | sed 's/^/  /'
  fi
}

# check DESCRIPTION COMMAND...: counts a pass when COMMAND succeeds.
check() {
  local what=$1
  shift
  if "$@"; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: $what"; fi
}

# expect_absent PATH DESCRIPTION: nothing was written at PATH.
expect_absent() {
  if [ -e "$1" ]; then failed=$((failed + 1)); echo "FAIL: $2: $1 exists"; else passed=$((passed + 1)); fi
}

# expect_not_in FILE PATTERN DESCRIPTION: FILE does not contain the fixed string PATTERN.
expect_not_in() {
  if grep -qF -- "$2" "$1"; then failed=$((failed + 1)); echo "FAIL: $3: '$2' in $(basename "$1")"; else
    passed=$((passed + 1)); fi
}

# expect_same_tree EXPECTED ACTUAL DESCRIPTION: the folders hold the same files, byte for byte (diff -r); the first
# differences are printed (and the status is 1) when they do not.
expect_same_tree() {
  if diff -r "$1" "$2" >/dev/null; then passed=$((passed + 1)); else
    failed=$((failed + 1)); echo "FAIL: $3"; diff -r "$1" "$2" | head -5
    return 1
  fi
}

# abs_push PATTERN: the first real ABS push whose file name holds PATTERN.
abs_push() {
  ls "$data"/abs/*"$1"*.h5 | head -1
}

# The batch of the --jobs, --shard and mpirun tests, in $files: one push each of five objects (rect1's force sensor
# is frozen, a failure) and a missing file at the end of the list.
batch_files() {
  files=()
  for pattern in 'shape=hex_a=0_v=50' 'shape=ellip1_a=0_v=20' 'shape=rect1' 'shape=ellip3_a=0_v=10' \
    'shape=butter_a=0_v=50'; do
    files+=("$(abs_push "$pattern")")
  done
  files+=("$tmp/missing.h5")
}

finish() {
  echo "$passed passed, $failed failed"
  [ "$failed" -eq 0 ]
}
