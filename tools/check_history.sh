#!/usr/bin/env bash
# Development history belongs in git, not in the user's manual, the docs or the code's comments: the README
# and docs/ describe the tool as it stands, and a comment says why the code is as it is, not which round of
# work, tuning seeds or discarded variant led there. This check fails (exit 1) and prints every offending
# line when README.md, docs/*.md or a comment in a .rs file carries such history:
#   - a "sitting" (a round of work), "tuning seeds/strips/sets", a variant "not kept" (anywhere);
#   - a commit-hash-like token of 7 to 40 hex digits (README and docs only: code and golden files hold
#     hashes and hex constants on purpose), not counting colour codes (#ff0000), plain numbers, words
#     and numbers in exponent notation (4.747472e-1);
#   - a reference to the tracker or to what the code did before (README, docs and code comments):
#     "issue N" / "issue #N", an item of one ("(item N)", ", item N)", "items N and M"), "used to <verb>"
#     (not "is used to <verb>", which says what a thing is for), "the old <noun>", "have/has always",
#     "previously", "formerly". "no longer" is not checked: it names a state as often as a change
#     ("a restart no longer improves").
# Usage: tools/check_history.sh (from anywhere; it checks the repository it lives in).
set -uo pipefail
cd "$(dirname "$0")/.."

docs=(README.md docs/*.md)
code_dirs=(src crates tests benches)
words='\bsitting\b|\btuning (seeds?|strips?|sets?)\b|\bnot kept\b'
# An issue or its items, and wording that compares the code with an earlier version of itself.
changes='\bissues? #?[0-9]+|\(items? [0-9]+\)|, items? [0-9]+\)|\bitems [0-9]+(, [0-9]+)* and [0-9]+\b'
changes+='|\bthe old [a-z]+|\bha(ve|s) always\b|\bpreviously\b|\bformerly\b'
# "used to <verb>" as a past habit ("the folder used to be replaced"); the passive "is used to compute"
# says what a thing is for, and "used to its end" has no verb: both are dropped from what is reported.
used_to='\bused to [a-z]+'
used_for='\b(is|are|was|were|be|been|being|gets?|got) used to [a-z]+|\bused to (the|a|an|its|their|this|that|these|those|each|every|all|any|some|one|it|them|his|her|our|your|my|no)\b'
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

# Issues, their items and earlier versions of the code, in the manual and the docs.
report "issues, their items or earlier behaviour in README/docs" "$(grep -nHiE "$changes" "${docs[@]}")"
report "\"used to\" (earlier behaviour) in README/docs" \
  "$(grep -nHiE "$used_to" "${docs[@]}" | grep -viE "$used_for")"

# The same in code comments, after the // only.
if ((${#existing_dirs[@]})); then
  report "issues, their items or earlier behaviour in code comments" \
    "$(grep -rnHiE --include='*.rs' "//.*($changes)" "${existing_dirs[@]}")"
  report "\"used to\" (earlier behaviour) in code comments" \
    "$(grep -rnHiE --include='*.rs' "//.*$used_to" "${existing_dirs[@]}" | grep -viE "//.*($used_for)")"
fi

exit $status
