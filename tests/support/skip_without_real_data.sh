# Sourced by the shell tests. A test that reads the real recordings is registered with PUSHPRED_REQUIRED_DATA naming
# their folder (tests/CMakeLists.txt, pushpred_needs_real_data); when that folder is missing it says why and exits
# with 77, which ctest counts as skipped rather than failed.
if [ -n "${PUSHPRED_REQUIRED_DATA:-}" ] && [ ! -d "$PUSHPRED_REQUIRED_DATA" ]; then
  echo "SKIPPED: this test reads the real recordings, and their folder $PUSHPRED_REQUIRED_DATA does not exist"
  exit 77
fi
