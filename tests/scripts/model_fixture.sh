# Sourced by the cli_*.sh tests that need the imported ICT model: sets FRIG_TEST_MODEL to
# the build tree's cached model file (the one tests/model_fixture.h uses), importing it
# with the frig command first when it is missing or older than the library. Returns 1
# when the ICT data is missing.
frig_test_model() {
  local shared="${FRIG_SHARED:-$FRIG_SOURCE_DIR/../shared}"
  FRIG_TEST_ICT="$shared/ict-facekit"
  [ -f "$FRIG_TEST_ICT/generic_neutral_mesh.obj" ] || return 1
  local cache="$FRIG_BINARY_DIR/test-tmp/model-cache"
  mkdir -p "$cache"
  FRIG_TEST_MODEL="$cache/ict.frigmodel"
  (
    flock 9
    if [ ! -f "$FRIG_TEST_MODEL" ] || [ "$FRIG_TEST_MODEL" -ot "$FRIG_BINARY_DIR/libfrig.a" ]; then
      "$FRIG_CLI" --quiet model import-ict "$FRIG_TEST_ICT" -o "$FRIG_TEST_MODEL" >/dev/null
    fi
  ) 9>"$cache/lock"
}

# Skip (exit 77) loudly, or fail when FRIG_REQUIRE_DATA is set.
frig_test_skip() {
  if [ -n "${FRIG_REQUIRE_DATA:-}" ] && [ "${FRIG_REQUIRE_DATA}" != 0 ]; then
    echo "FAIL (FRIG_REQUIRE_DATA is set, so this may not be skipped): $1"; exit 1
  fi
  echo; echo "*** SKIPPED: $1 ***"; echo; exit 77
}
