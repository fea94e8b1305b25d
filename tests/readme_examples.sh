#!/usr/bin/env bash
# Runs every ```sh block of README.md marked "<!-- tested: ... -->" on the line before it, from a
# scratch folder that looks like a clone (build/, scenes/, reports/, examples/ linked), with
# Debian's python3 first on PATH. Fails on the first command that fails.
#   readme_examples.sh SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
source="$1" build="$2" work="$3"
rm -rf "$work"
mkdir -p "$work"
ln -s "$build" "$work/build"
for d in scenes reports examples; do ln -s "$source/$d" "$work/$d"; done
export PATH="/usr/bin:$PATH"
blocks=0
tested=0
script=""
while IFS= read -r line; do
  if [ -z "$script" ] && [[ "$line" == "<!-- tested:"* ]]; then
    tested=1
  elif [ "$tested" = 1 ] && [ "$line" = '```sh' ]; then
    script="#"
  elif [ -n "$script" ] && [ "$line" = '```' ]; then
    blocks=$((blocks + 1))
    echo "== README block $blocks"
    printf '%s\n' "$script"
    (cd "$work" && bash -euo pipefail -c "$script") || { echo "README block $blocks failed" >&2; exit 1; }
    script=""
    tested=0
  elif [ -n "$script" ]; then
    script+=$'\n'"$line"
  else
    tested=0
  fi
done < "$source/README.md"
[ "$blocks" -ge 3 ] || { echo "only $blocks tested README blocks found" >&2; exit 1; }
ls "$work"/*.png >/dev/null
echo "$blocks README blocks ran"
