# Shared by the apps' command-line checks (apps/*/cli_test.sh); source it, then call
#   check NAME EXPECTED_EXIT PATTERN -- command...
# which runs the command, and fails (fail=1, output shown) unless it exits EXPECTED_EXIT and its
# output matches the extended regular expression PATTERN. $dir is a scratch folder removed on exit.
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
