#!/usr/bin/env bash
# Development history belongs in git, not in the user's manual, the docs or the code's comments: the README
# and docs/ describe the tool as it stands, and a comment says why the code is as it is, not which round of
# work, tuning seeds or discarded variant led there. This check fails (exit 1) and prints every offending
# line when README.md, docs/*.md or a comment in a .rs file carries such history:
#   - a "sitting" (a round of work), "tuning seeds/strips/sets", a variant "not kept" (anywhere);
#   - a commit-hash-like token of 7 to 40 hex digits (README and docs only: code and golden files hold
#     hashes and hex constants on purpose), not counting colour codes (#ff0000), plain numbers, words
#     and numbers in exponent notation (4.747472e-1);
#   - an issue round in a heading, "(issue 15, second sitting)" (README and docs).
# Usage: tools/check_history.sh (from anywhere; it checks the repository it lives in).
set -uo pipefail
cd "$(dirname "$0")/.."

docs=(README.md docs/*.md)
code_dirs=(src crates tests benches)
words='\bsitting\b|\btuning (seeds?|strips?|sets?)\b|\bnot kept\b'
status=0

report() {
  # $1: what was looked for; $2: the offending lines as file:line:text (empty: none).
  if [[ -n "$2" ]]; then
    echo "check_history: $1 (development history belongs in git):"
    echo "$2"
    status=1
  fi
}

# Words of a work diary, in the manual and the docs.
report "rounds of work, tuning seeds or variants not kept in README/docs" \
  "$(grep -nHiE "$words" "${docs[@]}")"

# The same in code comments: only what follows a // on the line (doc comments included), so that a
# string or an identifier the program needs is never flagged.
existing_dirs=()
for d in "${code_dirs[@]}"; do [[ -d $d ]] && existing_dirs+=("$d"); done
if ((${#existing_dirs[@]})); then
  report "rounds of work, tuning seeds or variants not kept in code comments" \
    "$(grep -rnHiE --include='*.rs' "//.*($words)" "${existing_dirs[@]}")"
fi

# Commit-hash-like tokens in the manual and the docs. A token counts when it is 7 to 40 hex digits
# with at least one letter a-f and one digit (so neither a number nor a word such as "defaced"), is not
# a colour (#ff0000) and is not a number in exponent notation.
report "commit-hash-like tokens in README/docs" "$(
  grep -nHoiE '(^|[^#0-9a-z_])[0-9a-f]{7,40}\b' "${docs[@]}" \
  | sed -E 's/^([^:]*:[0-9]+:)[^0-9a-fA-F]?/\1/' \
  | grep -iE ':[0-9a-f]*[a-f][0-9a-f]*$' \
  | grep -E ':[0-9a-fA-F]*[0-9][0-9a-fA-F]*$' \
  | grep -viE ':[0-9]+e[0-9]*$'
)"

# An issue round in a heading ("## Quality per second (issue 15, second sitting)").
report "issue rounds in README/docs headings" "$(grep -nHiE '^#{1,6} .*\bissue #?[0-9]+' "${docs[@]}")"

exit $status
