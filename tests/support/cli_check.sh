# Shared by the apps' command-line checks (apps/*/cli_test.sh); source it, then call
#   check NAME EXPECTED_EXIT PATTERN -- command...
# which runs the command, and fails (fail=1, output shown) unless it exits EXPECTED_EXIT and its
# output matches the extended regular expression PATTERN. $dir is a scratch folder removed on exit.
# The other helpers check the exit-code and output contract of docs/contributing.md (issue 12).
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
fail=0
check() {
  local name="$1" want="$2" pattern="$3"
  shift 4
  "$@" >"$dir/out" 2>&1
  local got=$?
  if [[ $got -ne $want ]] || ! grep -qE -e "$pattern" "$dir/out"; then
    echo "FAIL $name: exit $got (want $want), pattern '$pattern'"
    sed 's/^/    /' "$dir/out" | tail -20
    fail=1
  else
    echo "ok   $name"
  fi
}

# The last check's output has no byte a terminal would interpret (control characters other than
# newline and tab, DEL, bytes that are not UTF-8).
check_printable() {
  if LC_ALL=C grep -qP '[\x00-\x08\x0b-\x1f\x7f]' "$dir/out" || ! iconv -f UTF-8 -t UTF-8 "$dir/out" >/dev/null 2>&1; then
    echo "FAIL $1: raw control or non-UTF-8 bytes in the output"
    fail=1
  else
    echo "ok   $1"
  fi
}

# The last check's command wrote nothing to stdout before failing: it stopped before the work.
check_silent_stdout() {
  if grep -qvE "^$2" "$dir/out"; then
    echo "FAIL $1: output before the error (the work ran):"
    head -5 "$dir/out" | sed 's/^/    /'
    fail=1
  else
    echo "ok   $1"
  fi
}

# FOLDER holds exactly the names given (sorted, hidden ones included).
check_listing() {
  local name="$1" folder="$2"
  shift 2
  local got want
  got="$(ls -A "$folder" 2>/dev/null | sort | tr '\n' ' ')"
  want="$(printf '%s\n' "$@" | sed '/^$/d' | sort | tr '\n' ' ')"
  if [[ "$got" != "$want" ]]; then
    echo "FAIL $name: $folder holds '$got', want '$want'"
    fail=1
  else
    echo "ok   $name"
  fi
}

# Starts the command in the background, waits (up to 60 s) until a path matching the glob
# WAIT_FOR exists, then sends SIGNAL and waits for the command. Sets $signal_status to the
# command's status (128 + signal when the signal ended it) and returns 1 if WAIT_FOR never appeared.
#   signal_during SIGNAL WAIT_FOR -- command...
signal_during() {
  local sig="$1" pattern="$2"
  shift 3
  "$@" >"$dir/out" 2>&1 &
  local pid=$! seen=1
  for ((i = 0; i < 6000; ++i)); do
    if compgen -G "$pattern" >/dev/null; then
      seen=0
      break
    fi
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.01
  done
  kill -s "$sig" "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  signal_status=$?
  return $seen
}
