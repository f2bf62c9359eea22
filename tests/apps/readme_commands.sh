#!/usr/bin/env bash
# The README keeps exactly two set-up commands, and .ci/run runs the second one verbatim.
set -u
root=$1
source "$(dirname "$0")/cli_support.sh"
commands=$(sed -n '/<!-- setup-commands -->/,/<!-- \/setup-commands -->/p' "$root/README.md" | grep -E '^(bash|\./)' )
count=$(printf '%s\n' "$commands" | grep -c .)
if [ "$count" -eq 2 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: README has $count set-up commands, not 2"; fi
second=$(printf '%s\n' "$commands" | sed -n 2p)
if grep -qxF -- "$second" "$root/.ci/run"; then passed=$((passed + 1)); else
  failed=$((failed + 1)); echo "FAIL: .ci/run does not run the README's second command: $second"; fi
finish
