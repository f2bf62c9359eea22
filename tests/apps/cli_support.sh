# Sourced by the CLI tests: check helpers that count and print "N passed, M failed" at the end.
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

finish() {
  echo "$passed passed, $failed failed"
  [ "$failed" -eq 0 ]
}
