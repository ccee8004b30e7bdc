#!/usr/bin/env bash
# Documents and comments cite only files that are in the repository (issue 26):
# - no source, script, CMake or document file mentions the protocol notes file that once lived
#   outside the repository: its facts are in docs/protocols.md, which the comments cite;
# - every repository path of the form docs/... ending in .md that a file mentions exists;
# - every relative Markdown link [text](target) of a .md file points to a file that exists
#   (http:, https:, mailto: and #anchor links are not checked; a file link's #anchor is cut).
# build*/ folders and .git are not looked at. Usage: docs_links_test.sh SOURCE_DIR
set -u
root=${1:?usage: $0 SOURCE_DIR}
cd "$root" || exit 2

# Written in two parts so that this script does not find itself.
notes='PROTOCOL''-NOTES'
docs_path='(^|[^A-Za-z0-9_./-])doc''s/[A-Za-z0-9_./-]*\.md'

# Files to look at: C++, scripts, CMake, TOML, .in templates and documents.
mapfile -d '' files < <(find . \( -name .git -o -type d -name 'build*' \) -prune -o -type f \
  \( -name '*.h' -o -name '*.cpp' -o -name '*.sh' -o -name '*.py' -o -name '*.cmake' \
     -o -name CMakeLists.txt -o -name '*.md' -o -name '*.toml' -o -name '*.in' \
     -o -path './scripts/*' -o -path './.ci/*' \) -print0 | sort -z)
mapfile -d '' markdown < <(find . \( -name .git -o -type d -name 'build*' \) -prune -o -type f \
  -name '*.md' -print0 | sort -z)

# The Markdown links of a file, one "LINE<TAB>TARGET" a line. Paragraphs are joined first, so
# a link whose text wraps onto the next line is found; fenced code blocks and `code spans` are
# not Markdown links and are skipped.
md_links() {
  awk '
    function flush(   text, span, keep, at, line, link, target) {
      text = para
      # Blank out code spans, keeping their line breaks so line numbers stay right.
      while (match(text, /`[^`]*`/)) {
        span = substr(text, RSTART, RLENGTH)
        keep = span
        gsub(/[^\n]/, "", keep)
        text = substr(text, 1, RSTART - 1) keep substr(text, RSTART + RLENGTH)
      }
      at = 0
      while (match(text, /\[[^]]*\]\([^)]*\)/)) {
        link = substr(text, RSTART, RLENGTH)
        line = substr(text, 1, RSTART - 1)
        line = start + gsub(/\n/, "", line) + at
        target = link
        sub(/^\[[^]]*\]\(/, "", target)
        sub(/\)$/, "", target)
        if (target !~ /\n/) print line "\t" target
        # Count the line breaks of what is skipped, then go on after this link.
        skipped = substr(text, 1, RSTART + RLENGTH - 1)
        at += gsub(/\n/, "", skipped)
        text = substr(text, RSTART + RLENGTH)
      }
      para = ""
    }
    /^[ \t]*(```|~~~)/ { flush(); fenced = !fenced; next }
    fenced { next }
    /^[ \t]*$/ { flush(); next }
    { if (para == "") { para = $0; start = NR } else para = para "\n" $0 }
    END { flush() }
  ' "$1"
}

# The link finder must find links, or the link check proves nothing: a wrapped link, an image,
# a link after a code span, and nothing inside a fence or a code span.
sample=$(mktemp) || exit 2
trap 'rm -f "$sample"' EXIT
# shellcheck disable=SC2016  # the backquotes are the sample's Markdown, not a command
printf '%s\n' 'see [one](a.md#x) and `[no](code.md)` then [two' 'lines](b/c.md).' '' \
  '```' '[no](fenced.md)' '```' '![pic](d.png) [web](https://example.com)' > "$sample"
expected=$(printf '1\ta.md#x\n1\tb/c.md\n7\td.png\n7\thttps://example.com')
if [ "$(md_links "$sample")" != "$expected" ]; then
  echo "the Markdown link finder does not find the sample's links: the check is broken"
  md_links "$sample"
  exit 2
fi
if [ "${#files[@]}" -eq 0 ] || [ "${#markdown[@]}" -eq 0 ]; then
  echo "no files to check under $root: the check is broken"
  exit 2
fi

failed=0

hits=$(grep -HnF "$notes" "${files[@]}")
if [ -n "$hits" ]; then
  echo "these cite $notes, a file outside the repository (cite docs/protocols.md instead):"
  # shellcheck disable=SC2001  # every line's ./, not one substitution
  sed 's|^\./||' <<<"$hits"
  failed=1
fi

cited=0
while IFS= read -r hit; do
  place=${hit%%:*}; place=${place#./}; rest=${hit#*:}; line=${rest%%:*}; match=${rest#*:}
  path=${match#"${match%%doc*}"}
  cited=$((cited + 1))
  if [ ! -f "$path" ]; then
    echo "$place:$line: cites $path, which is not in the repository"
    failed=1
  fi
done < <(grep -HnoE "$docs_path" "${files[@]}")

checked=0
for file in "${markdown[@]}"; do
  dir=$(dirname "$file")
  while IFS=$'\t' read -r line target; do
    case $target in http://* | https://* | mailto:* | '#'*) continue ;; esac
    path=${target%%#*}
    path=${path%% *}                # a link title: [text](file "title")
    path=${path#<}; path=${path%>}  # [text](<file>)
    case $path in /*) resolved=.$path ;; *) resolved=$dir/$path ;; esac
    checked=$((checked + 1))
    if [ -z "$path" ] || [ ! -e "$resolved" ]; then
      echo "${file#./}:$line: links to $target, which does not exist"
      failed=1
    fi
  done < <(md_links "$file")
done

# Nothing found to check would prove nothing: README.md links to docs/protocols.md.
if [ "$checked" -eq 0 ] || [ "$cited" -eq 0 ]; then
  echo "found $checked relative Markdown links and $cited docs/ citations: the check is broken"
  exit 2
fi
if [ "$failed" -ne 0 ]; then
  exit 1
fi
echo "${#files[@]} files cite no file outside the repository; $cited docs/ citations and" \
  "$checked relative Markdown links in ${#markdown[@]} .md files point to files that exist"
