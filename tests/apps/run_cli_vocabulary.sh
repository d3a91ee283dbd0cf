#!/bin/bash
# One tool against docs/cli.md's vocabulary: its --help lists every flag the table gives
# it, and each renamed flag's old spelling is still read (a note on stderr, then --help's
# exit 0).
# usage: run_cli_vocabulary.sh TOOL [SUBCOMMAND] -- FLAG... [-- OLD=NEW...]
set -u
tool=$1; shift
sub=()
if [ "$1" != "--" ]; then sub=("$1"); shift; fi
shift  # --
flags=(); renamed=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do flags+=("$1"); shift; done
[ $# -gt 0 ] && shift
renamed=("$@")
fails=0
help=$("$tool" "${sub[@]}" --help 2>&1 </dev/null)
for f in "${flags[@]}"; do
  # TCLAP prints "-o <DIR>,  --out <DIR>" or "--out <DIR>" or "-q,  --quiet".
  if ! grep -qE -- "(^|[[:space:],])${f}( |,|$)" <<<"$help"; then
    echo "FAIL: --help lacks $f"; fails=$((fails+1))
  fi
done
for pair in "${renamed[@]}"; do
  old=${pair%%=*}; new=${pair#*=}
  err=$("$tool" "${sub[@]}" "$old" 1 --help 2>&1 >/dev/null </dev/null); rc=$?
  if [ "$rc" != 0 ]; then echo "FAIL: $old 1 --help exited $rc: $err"; fails=$((fails+1)); fi
  if ! grep -q -- "$old is now $new" <<<"$err"; then echo "FAIL: no note for $old: $err"; fails=$((fails+1)); fi
done
[ "$fails" = 0 ] && echo "vocabulary holds" || exit 1
