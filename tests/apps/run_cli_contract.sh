#!/bin/bash
# The command-line contract of one tool (issue 16): a usage error (a bad value, an unknown
# flag, a missing argument) prints "usage error" on stderr, exits 2 and writes nothing;
# --help and --version exit 0 and run nothing, even at the end of a full command; `-c ''`
# is a usage error.
# usage: run_cli_contract.sh TMPDIR TOOL NUMERIC_FLAG [SUBCOMMAND] -- ARGS...
# (NUMERIC_FLAG: a flag taking a number, given "fifty"; ARGS: a valid command whose outputs
# are all under $TMPDIR/out; the literal word OUT stands for that path)
set -u
tmp=$1; tool=$2; numeric=$3; shift 3
sub=()
if [ "$1" != "--" ]; then sub=("$1"); shift; fi
shift  # --
mkdir -p "$tmp"
out="$tmp/out"
args=()
for a in "$@"; do args+=("${a//OUT/$out}"); done
fails=0
check() {  # check NAME EXPECTED_STATUS STDERR_PATTERN ARGS...
  local name=$1 want=$2 pattern=$3; shift 3
  rm -rf "$out" "$out".* "$tmp/err"
  "$tool" "${sub[@]}" "$@" >/dev/null 2>"$tmp/err" </dev/null
  local rc=$?
  if [ "$rc" != "$want" ]; then echo "FAIL $name: exit $rc, expected $want"; cat "$tmp/err"; fails=$((fails+1)); fi
  if [ -n "$pattern" ] && ! grep -q "$pattern" "$tmp/err"; then echo "FAIL $name: stderr lacks '$pattern'"; cat "$tmp/err"; fails=$((fails+1)); fi
  if compgen -G "$out*" >/dev/null; then echo "FAIL $name: wrote $(ls -d "$out"*)"; fails=$((fails+1)); fi
}
check "bad value" 2 "usage error" "${args[@]}" "$numeric" fifty
check "bad value first" 2 "usage error" "$numeric" fifty "${args[@]}"
check "unknown flag" 2 "usage error" "${args[@]}" --no-such-flag
check "help at the end" 0 "" "${args[@]}" --help
check "help alone" 0 ""  --help
check "version" 0 "" --version
check "missing argument" 2 "usage error"
# An empty configuration name (`-c ''`, an unset variable) is not a run with the defaults.
check "empty config" 2 "usage error: -c/--config: an empty file name" "${args[@]}" -c ''
[ "$fails" = 0 ] && echo "command-line contract holds" || exit 1
