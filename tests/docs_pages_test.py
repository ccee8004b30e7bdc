"""Facts of the manual that the source tree can check without the gateway running (issue 54,
item 8). Usage: docs_pages_test.py CHECK SOURCE_DIR [PAGE...], CHECK one of

  contents    each PAGE's "Contents:" list names every heading of the page (## to ####), in
              order, nested as the headings are, each linked to its own heading's anchor;
  examples    every examples/... path the README and docs/ name exists, and a device profile
              named as devices/NAME.toml (the examples folder left out) appears only as a
              [[sensor]] device = "..." key, which is relative to its configuration file;
  ser2net     every ser2net YAML block in docs/ carries `chardelay: false`, and Debian's
              ser2net reads it without an error (with its tty and port made local);
  audit-who   docs/operations.md's audit table: its door row names every door the code records
              a change under (a WriteOrigin in the sources), and its who row says who for each.

Exit 0 pass, 1 fail (what is wrong printed), 2 a usage error, 77 skipped (ser2net missing)."""
import glob
import os
import random
import re
import socket
import subprocess
import sys
import tempfile


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def outside_fences(text):
    """The lines of a Markdown text that are not inside a fenced code block: (number, line)."""
    fence = None
    for number, line in enumerate(text.split("\n"), 1):
        marker = re.match(r" {0,3}(```|~~~)", line)
        if marker:
            fence = None if fence == marker.group(1) else (fence or marker.group(1))
            continue
        if fence is None:
            yield number, line


def anchor_of(title, seen):
    """A heading's anchor by GitHub's rules (as tests/docs_links_test.sh computes them)."""
    anchor = re.sub(r"[^\w\- ]", "", title.replace("`", "").lower()).replace(" ", "-")
    count = seen.get(anchor, 0)
    seen[anchor] = count + 1
    return anchor if count == 0 else "%s-%d" % (anchor, count)


def check_contents(root, pages):
    problems = []
    for page in pages:
        text = read(os.path.join(root, page))
        headings, seen = [], {}
        for _, line in outside_fences(text):
            m = re.match(r"(#{2,4})\s+(.*?)\s*$", line)
            if m:
                headings.append((len(m.group(1)) - 2, m.group(2), anchor_of(m.group(2), seen)))
        start = text.find("\nContents:\n\n")
        if start < 0:
            problems.append("%s: no \"Contents:\" list" % page)
            continue
        listed = []
        for line in text[start:].split("\n")[3:]:
            m = re.match(r"( *)- \[(.*)\]\(#([^)]*)\)\s*$", line)
            if not m:
                break
            listed.append((len(m.group(1)) // 2, m.group(2), m.group(3)))
        if not headings:
            problems.append("%s: no headings found: the check is broken" % page)
        for i in range(max(len(headings), len(listed))):
            want = headings[i] if i < len(headings) else None
            have = listed[i] if i < len(listed) else None
            if want != have:
                problems.append("%s: contents entry %d is %s, the page's heading there is %s"
                                % (page, i + 1, have, want))
                break
    return problems


def manual_pages(root):
    return [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "*.md")))


def check_examples(root, _pages):
    problems, named = [], 0
    for path in manual_pages(root):
        page = os.path.relpath(path, root)
        for number, line in enumerate(read(path).split("\n"), 1):
            for m in re.finditer(r"(?<![\w./-])examples/[\w./-]*[\w/]", line):
                named += 1
                if not os.path.exists(os.path.join(root, m.group(0))):
                    problems.append("%s:%d: names %s, which is not in the source tree"
                                    % (page, number, m.group(0)))
            for m in re.finditer(r"(?<![\w./-])devices/[\w.-]+\.toml", line):
                if not re.search(r'device = "$', line[:m.start()]):
                    problems.append("%s:%d: names %s: the example profiles are in examples/devices/"
                                    " (only a device = \"...\" key is relative to its file)"
                                    % (page, number, m.group(0)))
    if named == 0:
        problems.append("no examples/ path found in the manual: the check is broken")
    return problems


def free_port():
    """A random port nothing listens on, below the kernel's ephemeral range (32768 up) so no
    connect() on the machine takes it before the demo binds it."""
    while True:
        port = random.randint(20000, 32767)
        try:
            with socket.socket() as s:
                s.bind(("127.0.0.1", port))
            return port
        except OSError:
            pass


def ser2net_blocks(root):
    """The ```yaml blocks of docs/ that configure ser2net: (page, line, text)."""
    for path in manual_pages(root):
        text = read(path)
        for m in re.finditer(r"```yaml\n(.*?)```", text, re.S):
            if "connector: serialdev" in m.group(1):
                yield os.path.relpath(path, root), text[:m.start()].count("\n") + 2, m.group(1)


def check_ser2net(root, _pages):
    problems = []
    blocks = list(ser2net_blocks(root))
    if not blocks:
        return ["no ser2net YAML block found in the manual: the check is broken"]
    for page, line, block in blocks:
        if not re.search(r"^\s+chardelay: false\s*$", block, re.M):
            problems.append("%s:%d: the ser2net example lacks `chardelay: false`: ser2net then "
                            "holds every reply back before sending it on" % (page, line))
    if subprocess.run(["sh", "-c", "command -v ser2net"], capture_output=True).returncode != 0:
        if problems:
            return problems
        print("ser2net is not installed: its reading of the examples is not checked")
        sys.exit(77)
    with tempfile.TemporaryDirectory() as scratch:
        for page, line, block in blocks:
            # Its tty made one that exists, its port a free one on loopback: ser2net opens the
            # tty only when a client connects, and this one gets none.
            local = re.sub(r"serialdev,[^,]+,", "serialdev,/dev/null,", block)
            local = re.sub(r"tcp,(\d+)", "tcp,127.0.0.1,%d" % free_port(), local)
            config = os.path.join(scratch, "ser2net.yaml")
            with open(config, "w") as f:
                f.write(local)
            try:
                run = subprocess.run(["ser2net", "-n", "-d", "-c", config], capture_output=True,
                                     text=True, timeout=3)
                output = run.stdout + run.stderr
                if run.returncode != 0:
                    output += "\n(exit %d)" % run.returncode
            except subprocess.TimeoutExpired as running:  # it took the file and served
                output = (running.stdout or b"").decode() + (running.stderr or b"").decode()
            for said in output.splitlines():
                if re.search(r"Unknown config item|[Ee]rror|[Ii]nvalid", said):
                    problems.append("%s:%d: ser2net does not take the example: %s"
                                    % (page, line, said))
    return problems


def code_doors(root):
    """Every door the sources record a change under: WriteOrigin{"door", ...} and
    origin = {"door", ...}."""
    doors = set()
    for path in glob.glob(os.path.join(root, "*", "**", "*.cpp"), recursive=True) + \
            glob.glob(os.path.join(root, "*", "**", "*.h"), recursive=True):
        if "/tests/" in path or "/build" in path or "/fuzz/" in path or "/bench/" in path:
            continue
        text = read(path)
        doors.update(re.findall(r'WriteOrigin\{"([^"]+)"', text))
        doors.update(re.findall(r'origin(?: =|\{) ?\{"([^"]+)",', text))
        doors.update(re.findall(r'WriteOrigin origin\{"([^"]+)"', text))
    return doors


def check_audit_who(root, _pages):
    text = read(os.path.join(root, "docs", "operations.md"))
    rows = {}
    for m in re.finditer(r"^\| (door|who) \| (.*) \|$", text, re.M):
        rows.setdefault(m.group(1), m.group(2))  # the first: the audit trail's table
    doors = code_doors(root)
    if len(doors) < 4:
        return ["found only the doors %s in the sources: the check is broken" % sorted(doors)]
    if set(rows) != {"door", "who"}:
        return ["docs/operations.md has no audit table with a door and a who row"]
    problems = []
    for door in sorted(doors):
        if "`%s`" % door not in rows["door"]:
            problems.append("docs/operations.md's door row does not name door `%s`" % door)
        if "`%s`:" % door not in rows["who"]:
            problems.append("docs/operations.md's who row does not say who for door `%s` "
                            "(as `%s`: ...)" % (door, door))
    return problems


CHECKS = {"contents": check_contents, "examples": check_examples, "ser2net": check_ser2net,
          "audit-who": check_audit_who}


def main():
    if len(sys.argv) < 3 or sys.argv[1] not in CHECKS:
        print(__doc__)
        return 2
    problems = CHECKS[sys.argv[1]](sys.argv[2], sys.argv[3:])
    for problem in problems:
        print(problem)
    if not problems:
        print("%s: the manual holds" % sys.argv[1])
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
