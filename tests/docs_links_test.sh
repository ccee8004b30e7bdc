#!/usr/bin/env bash
# Documents and comments cite only files that are in the repository (issue 26):
# - no source, script, CMake or document file mentions the protocol notes file that once lived
#   outside the repository: its facts are in docs/protocols.md, which the comments cite;
# - every repository path of the form docs/... ending in .md that a file mentions exists;
# - every relative Markdown link [text](target) of a .md file points to a file that exists
#   (http:, https: and mailto: links are not checked);
# - every anchor a .md file links to, its own (#anchor) or another .md file's (page.md#anchor),
#   exists there (issue 27): a heading's anchor by GitHub's rules (the heading's text without
#   its #'s, lowercased, every character but letters, digits, _, - and space dropped (backticks
#   and other punctuation), each space a -, and -1, -2, ... after a repeated one), or an
#   <a id="..."> / <a name="..."> of the file;
# - every citation of a documentation section, in any file looked at, names a heading of the
#   file it cites (issue 27). A citation is one of
#       (README, "Section Title")   README "Section Title"   README's "Section Title"
#       docs/<page>.md, "Section Title"   (also README.md; also docs/<page>.md "..." and 's)
#   README being the top-level README.md, a docs/ path that file of the source tree. It may
#   wrap onto the next line, whose comment marker (//, #, *, --) is then skipped, and its quotes
#   may be escaped (\") inside a C++ string. Citation and headings are compared without the
#   headings' #'s, without backticks, with runs of white space as one space, case ignored. A
#   citation that is not a whole heading is accepted when it is the start of exactly one heading
#   of that file, ending where a word ends ("`tiltgate scan`" names "`tiltgate scan`: finding
#   the sensors on a bus"); the start of two or more headings is ambiguous and fails. A failure
#   names the other .md files that have such a heading, if any (where the section moved).
#   This script's own comments are not looked at for citations.
# build*/ folders and .git are not looked at. Usage: docs_links_test.sh SOURCE_DIR
set -u
root=${1:?usage: $0 SOURCE_DIR}
cd "$root" || exit 2

# Written in two parts so that this script does not find itself.
notes='PROTOCOL''-NOTES'
docs_path='(^|[^A-Za-z0-9_./-])doc''s/[A-Za-z0-9_./-]*\.md'

# Files to look at: C++, scripts, CMake, TOML, .in templates, HTML, documents, and packaging/
# (the service unit, the maintainer scripts).
mapfile -d '' files < <(find . \( -name .git -o -type d -name 'build*' \) -prune -o -type f \
  \( -name '*.h' -o -name '*.cpp' -o -name '*.sh' -o -name '*.py' -o -name '*.cmake' \
     -o -name CMakeLists.txt -o -name '*.md' -o -name '*.toml' -o -name '*.in' -o -name '*.html' \
     -o -path './scripts/*' -o -path './.ci/*' -o -path './packaging/*' \) -print0 | sort -z)
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

# Headings, anchors and citations, in Perl (Debian's perl-base is always there). Modes:
#   anchors FILE        the anchors of a .md file's headings and <a id>s, one a line
#   citations FILE      the citations in FILE, as LINE<TAB>CITED FILE<TAB>TITLE
#   check SELF          checks the citations in the NUL-separated files on standard input
#                       against the cited files' headings (the current folder is the source
#                       tree); prints one FAIL<TAB>message line per bad citation, then
#                       CITED<TAB>count. SELF (this script) is left out.
# shellcheck disable=SC2016  # Perl, not shell: its $ are its own
read -r -d '' sections_pl <<'PERL'
use strict;
use warnings;
use Encode qw(decode);
binmode STDOUT, ':encoding(UTF-8)';

sub slurp {
  my ($path) = @_;
  open(my $in, '<:raw', $path) or return undef;
  local $/;
  my $bytes = <$in>;
  close $in;
  return decode('UTF-8', $bytes // '');
}

# A heading's text as shown: inline code and links as their text, HTML tags and emphasis
# stars dropped, white space runs as one space.
sub shown {
  my ($text) = @_;
  $text =~ s/<[^>]*>//g;
  $text =~ s/!?\[([^\]]*)\]\([^)]*\)/$1/g;
  $text =~ s/`//g;
  $text =~ s/\*//g;
  $text =~ s/\s+/ /g;
  $text =~ s/^ | $//g;
  return $text;
}

# The headings of a Markdown file (outside fenced code blocks) and its anchors.
sub headings {
  my ($path) = @_;
  my $text = slurp($path);
  return ([], []) unless defined $text;
  my (@titles, @anchors, %seen);
  my $fence = '';
  for my $line (split /\n/, $text) {
    if ($line =~ /^ {0,3}(`{3,}|~{3,})/) {
      my $marker = $1;
      if ($fence eq '') { $fence = $marker; next; }
      if (substr($marker, 0, 1) eq substr($fence, 0, 1) && length($marker) >= length($fence)
          && $line =~ /^ {0,3}[`~]+\s*$/) { $fence = ''; }
      next;
    }
    next if $fence ne '';
    while ($line =~ /<a\s+(?:id|name)="([^"]+)"/g) { push @anchors, $1; }
    next unless $line =~ /^ {0,3}#{1,6}(?:[ \t]+(.*?))?(?:[ \t]+#+)?[ \t]*$/;
    my $title = shown($1 // '');
    push @titles, $title;
    (my $anchor = lc $title) =~ s/[^\p{Word}\- ]//g;
    $anchor =~ tr/ /-/;
    my $n = $seen{$anchor}++;
    push @anchors, $n ? "$anchor-$n" : $anchor;
  }
  return (\@titles, \@anchors);
}

my $comment = qr{(?://+|\#+|\*+|--)};
my $gap = qr{[ \t]*(?:\n[ \t]*$comment?[ \t]*)?};
my $citation = qr{
  (?<![A-Za-z0-9_./-])
  (README(?:\.md)?|docs/[A-Za-z0-9_./-]+\.md)
  (?:,|'s)? $gap
  \\?" (?=[A-Za-z0-9`\[])
  ((?:[^"\\\n]|\n[ \t]*$comment?[ \t]*)+?)
  \\?"
}x;

# The citations of a file: [line, cited file, title as written, one line].
sub citations {
  my ($path) = @_;
  my $text = slurp($path);
  return () unless defined $text;
  my @found;
  while ($text =~ /$citation/g) {
    my ($doc, $title) = ($1, $2);
    my $line = 1 + (substr($text, 0, $-[0]) =~ tr/\n//);
    $title =~ s/\n[ \t]*$comment?[ \t]*/ /g;
    $doc = 'README.md' if $doc eq 'README';
    push @found, [$line, $doc, shown($title)];
  }
  return @found;
}

sub key { my ($text) = @_; return lc shown($text); }

# Whether TITLE names a heading of TITLES: '' when it does, else why not.
sub verdict {
  my ($title, $titles) = @_;
  my $want = key($title);
  return '' if grep { key($_) eq $want } @$titles;
  my @starts = grep {
    my $have = key($_);
    index($have, $want) == 0 && substr($have, length $want, 1) !~ /\w/
  } @$titles;
  return '' if @starts == 1 && $want =~ /\w$/;
  return 'which starts ' . scalar(@starts) . ' headings there ("' . join('", "', @starts)
       . '"): name one of them whole' if @starts > 1;
  return 'which is not a heading there';
}

my $mode = shift @ARGV // '';
if ($mode eq 'anchors') {
  my (undef, $anchors) = headings($ARGV[0]);
  print "$_\n" for @$anchors;
} elsif ($mode eq 'citations') {
  print join("\t", @$_), "\n" for citations($ARGV[0]);
} elsif ($mode eq 'check') {
  my $self = $ARGV[0] // '';
  local $/ = "\0";
  my @files = map { chomp; $_ } <STDIN>;
  my @markdown = sort grep { m{(^|/)README\.md$|^(\./)?docs/[^/]+\.md$} } @files;
  my (%titles, $count);
  for my $path (@files) {
    (my $place = $path) =~ s{^\./}{};
    next if $place eq $self;
    for my $found (citations($path)) {
      my ($line, $doc, $title) = @$found;
      $count++;
      $titles{$doc} //= (-f $doc ? (headings($doc))[0] : undef);
      if (!defined $titles{$doc}) {
        print "FAIL\t$place:$line: cites $doc, \"$title\": $doc is not in the repository\n";
        next;
      }
      my $why = verdict($title, $titles{$doc});
      next if $why eq '';
      my @elsewhere;
      for my $other (@markdown) {
        (my $name = $other) =~ s{^\./}{};
        next if $name eq $doc;
        $titles{$name} //= (headings($name))[0];
        push @elsewhere, $name if verdict($title, $titles{$name}) eq '';
      }
      my $hint = @elsewhere ? ' (a heading of ' . join(', ', @elsewhere) . ')' : '';
      print "FAIL\t$place:$line: cites $doc, \"$title\", $why$hint\n";
    }
  }
  print 'CITED', "\t", $count // 0, "\n";
} else {
  die "usage: MODE (anchors FILE | citations FILE | check SELF < FILES)\n";
}
PERL
sections() { perl -e "$sections_pl" -- "$@"; }

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
# The anchors and the citations must be found as GitHub and a reader find them, or their
# checks prove nothing: a heading with code and punctuation, a repeated heading, an <a id>, no
# heading inside a fence; a citation wrapped onto the next comment line, one with code, one
# with escaped quotes, one with 's, and none for a quote that follows no file name.
# shellcheck disable=SC2016  # the backquotes are the samples' Markdown, not a command
printf '%s\n' '# Title' '## `[server]`: the Modbus/TCP side' '```' '# not a heading' '```' \
  '## Title' '- <a id="threads"></a>**Threads.**' '### Set up ###' > "$sample"
expected=$(printf 'title\nserver-the-modbustcp-side\ntitle-1\nthreads\nset-up')
if [ "$(sections anchors "$sample")" != "$expected" ]; then
  echo "the anchor finder does not find the sample's anchors: the check is broken"
  sections anchors "$sample"
  exit 2
fi
readme='READ''ME' docs='doc''s'
printf '%s\n' "// see ($readme, \"Quick start\") and ${docs}/x.md, \"Two" '// words" and "other";' \
  "# $readme \"\`Three\`\" and $readme's \"Four\"" "s = \"($readme, \\\"Five\\\")\";" > "$sample"
expected=$(printf '1\tREADME.md\tQuick start\n1\tdocs/x.md\tTwo words\n3\tREADME.md\tThree\n3\tREADME.md\tFour\n4\tREADME.md\tFive')
if [ "$(sections citations "$sample")" != "$expected" ]; then
  echo "the citation finder does not find the sample's citations: the check is broken"
  sections citations "$sample"
  exit 2
fi
# A whole heading, a heading's unique start, case and backticks aside, pass; an ambiguous
# start, half a word and a missing heading fail.
scratch=$(mktemp -d) || exit 2
trap 'rm -f "$sample"; rm -rf "$scratch"' EXIT
# shellcheck disable=SC2016  # the backquotes are the sample's Markdown, not a command
printf '%s\n' '# Top' '## Alpha beta' '## Alpha gamma' '## `delta`: more' > "$scratch/README.md"
printf '%s\n' "($readme, \"alpha BETA\") ($readme, \"Delta\") ($readme, \"Top\")" \
  "($readme, \"Alpha\") ($readme, \"Alpha gam\") ($readme, \"Missing\")" > "$scratch/a.h"
verdicts=$(cd "$scratch" && printf '%s\0' ./README.md ./a.h | sections check - | cut -f1 | sort | uniq -c)
if [ "$(tr -s ' ' <<<"$verdicts")" != "$(printf ' 1 CITED\n 3 FAIL')" ]; then
  echo "the citation check does not judge the sample's citations right: the check is broken"
  (cd "$scratch" && printf '%s\0' ./README.md ./a.h | sections check -)
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

# The anchors of every .md file, by its path from the source tree ("docs/protocols.md").
declare -A anchors
for file in "${markdown[@]}"; do
  anchors[${file#./}]=$'\n'$(sections anchors "$file")$'\n'
done

checked=0
anchored=0
for file in "${markdown[@]}"; do
  dir=$(dirname "$file")
  while IFS=$'\t' read -r line target; do
    case $target in http://* | https://* | mailto:*) continue ;; esac
    target=${target%% *}                  # a link title: [text](file "title")
    target=${target#<}; target=${target%>}  # [text](<file>)
    path=${target%%#*}
    anchor=
    case $target in *'#'*) anchor=${target#*#} ;; esac
    if [ -n "$path" ]; then
      case $path in /*) resolved=.$path ;; *) resolved=$dir/$path ;; esac
      checked=$((checked + 1))
      if [ ! -e "$resolved" ]; then
        echo "${file#./}:$line: links to $target, which does not exist"
        failed=1
        continue
      fi
      linked=$(realpath -m --relative-to=. "$resolved")
    else
      linked=${file#./}
    fi
    [ -n "$anchor" ] || continue
    case $linked in *.md) ;; *) continue ;; esac  # an anchor of another kind of file
    anchored=$((anchored + 1))
    if [[ ${anchors[$linked]-} != *$'\n'"$anchor"$'\n'* ]]; then
      echo "${file#./}:$line: links to $target, but $linked has no heading or <a id> with the anchor #$anchor"
      failed=1
    fi
  done < <(md_links "$file")
done

# Citations of a document's sections name its headings.
report=$(printf '%s\0' "${files[@]}" | sections check tests/docs_links_test.sh) || exit 2
sections_cited=$(sed -n 's/^CITED\t//p' <<<"$report")
bad=$(sed -n 's/^FAIL\t//p' <<<"$report")
if [ -n "$bad" ]; then
  echo "these cite a section by a title that is not a heading of the file they cite:"
  echo "$bad"
  failed=1
fi

# Nothing found to check would prove nothing: README.md links to the docs/ pages and their
# headings, and code comments cite docs/protocols.md by heading.
if [ "$checked" -eq 0 ] || [ "$cited" -eq 0 ] || [ "$anchored" -eq 0 ] \
   || [ "${sections_cited:-0}" -eq 0 ]; then
  echo "found $checked relative Markdown links, $anchored anchors linked, $cited docs/ citations" \
    "and ${sections_cited:-0} citations of sections: the check is broken"
  exit 2
fi
if [ "$failed" -ne 0 ]; then
  exit 1
fi
echo "${#files[@]} files cite no file outside the repository; $cited docs/ citations and" \
  "$checked relative Markdown links in ${#markdown[@]} .md files point to files that exist;" \
  "$anchored linked anchors and $sections_cited citations of sections name headings that exist"
