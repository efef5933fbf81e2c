#!/usr/bin/env bash
# The frig command: version, help, exit codes, frig info on good and bad files.
set -u
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
tmp="$FRIG_BINARY_DIR/test-tmp/cli_basics"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"

check '"$F" --version | grep -q "^frig [0-9]\+\.[0-9]\+\.[0-9]\+"'
check '"$F" help | grep -q "info"'
check '"$F" help info | grep -q "usage: frig info"'
check '"$F" help params | grep -q "detect.scale_factor"'
"$F" >/dev/null 2>&1; check '[ $? = 2 ]'
"$F" no-such-command 2>"$tmp/err"; check '[ $? = 2 ]'
check 'grep -q "unknown command" "$tmp/err"'
"$F" --threads x info 2>/dev/null; check '[ $? = 2 ]'
"$F" --set detect.nonsense=1 info x 2>"$tmp/err"; check '[ $? = 2 ]'
check 'grep -q "unknown parameter" "$tmp/err"'
"$F" info 2>/dev/null; check '[ $? = 2 ]'

# frig info: a good PNG written by the library itself through 'frig info'-independent means:
printf '\x89PNG\r\n\x1a\n' > "$tmp/cut.png"
: > "$tmp/empty.jpg"
"$F" info "$tmp/cut.png" "$tmp/empty.jpg" "$tmp/missing.jpg" > "$tmp/out"; check '[ $? = 1 ]'
check '[ $(wc -l < "$tmp/out") = 3 ]'
# frig starts itself again with glibc's huge pages (cli/main.c) unless GLIBC_TUNABLES is set: the
# same output and exit code either way.
env -u GLIBC_TUNABLES "$F" info "$tmp/cut.png" "$tmp/empty.jpg" "$tmp/missing.jpg" > "$tmp/out_restart"; check '[ $? = 1 ]'
GLIBC_TUNABLES= "$F" info "$tmp/cut.png" "$tmp/empty.jpg" "$tmp/missing.jpg" > "$tmp/out_plain"; check '[ $? = 1 ]'
check 'cmp -s "$tmp/out_restart" "$tmp/out" && cmp -s "$tmp/out_plain" "$tmp/out"'
check 'grep -q "empty.jpg: cannot read: .*empty (0 bytes)" "$tmp/out"'
check 'grep -q "missing.jpg: cannot read: .*no such file" "$tmp/out"'

shared="${FRIG_SHARED:-$FRIG_SOURCE_DIR/../shared}"
if [ -d "$shared/photos" ]; then
  "$F" info "$shared/photos/landmarks_300w_lfpw/lfpw_image_0010.png" "$shared/photos/lfw_tony_blair/"*.jpg > "$tmp/out"
  check '[ $? = 0 ]'
  check '[ $(wc -l < "$tmp/out") = 101 ]'
  check 'grep -q "Tony_Blair_0001.jpg: 150x150, 3 channels, 8-bit, orientation 1, JPEG" "$tmp/out"'
  # Every photo in the shared sets must be readable.
  find "$shared/photos" -type f \( -iname '*.jpg' -o -iname '*.jpeg' -o -iname '*.png' \) -print0 |
    xargs -0 "$F" info > "$tmp/all" 2>&1
  check '[ $? = 0 ]'
  grep "cannot read" "$tmp/all" | head
else
  echo "*** SKIPPED part: no shared photos at $shared ***"
  [ -n "${FRIG_REQUIRE_DATA:-}" ] && fail=1
fi
exit $fail
