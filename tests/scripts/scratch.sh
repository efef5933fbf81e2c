# Sourced by a shell test after it made its scratch folder "$tmp": the folder is removed when the
# test exits with 0 (the suite's two builds would otherwise keep gigabytes of workspaces and
# models), kept for a look when it failed or when FRIG_KEEP_TEST_TMP is set.
scratch_cleanup() {
  local rc=$?
  if [ "$rc" = 0 ] && [ "${FRIG_KEEP_TEST_TMP:-0}" = 0 ] && [ -n "${tmp:-}" ]; then rm -rf "$tmp"; fi
  exit "$rc"
}
trap scratch_cleanup EXIT
