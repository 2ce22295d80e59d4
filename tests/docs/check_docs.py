#!/usr/bin/env python3
"""check_docs.py REPO_ROOT BIN_DIR: the documentation cannot drift from the programs.

Fails (exit 1, one line per problem) when
  * a gf-* program in BIN_DIR has no page docs/programs/<program>.md;
  * an option (long name) listed by `<program> --help` is not mentioned on its page;
  * a row of a page's option tables names an option that `--help` no longer lists
    (a removed or renamed option);
  * a page docs/programs/<name>.md exists for no program in BIN_DIR;
  * a relative link [text](path) or [text](path#anchor) in README.md, CHANGELOG.md or
    any docs/**/*.md points to a file that does not exist, or to a heading that the
    target markdown file does not have;
  * a repository path quoted in README.md or docs/**/*.md does not exist in the tree. A quoted
    repository path is a token of an inline code span (`...`, outside fenced blocks; tokens
    split at white space; quotes, brackets, commas and semicolons around it stripped; a ':' or
    '#' and what follows, a line number or an anchor, dropped) that contains a '/' and whose
    first component is a top-level directory of REPO_ROOT, relative to it (lib, tools, tests,
    pipelines, python, bench, docs, cmake, .ci, ...). Not checked: tokens with a glob or
    placeholder character (* ? [ ] { } < > $), and paths in a directory that REPO_ROOT/.gitignore
    ignores by a directory pattern ("/build*/", "/runs/", "/figures/", "/python/build/",
    "*.egg-info/": outputs of the build and the pipelines, absent from a fresh clone).
    CHANGELOG.md's paths are history and are not checked; its links are. The check first runs on
    a planted page and fails unless it reports exactly the planted dangling path;
  * the version is not the same in its one place (CMakeLists.txt's project(... VERSION x.y.z)),
    every `version:` of CITATION.cff and the first line of every program's --version, or
    CHANGELOG.md has no section "## x.y.z" or "## Unreleased" above it (docs/releases.md);
  * a program's --version does not name the licence of LICENSE (BSD-3-Clause);
  * a --help text (a program's or a command's) spells a symbol in ASCII (xi, nu, mu, theta, ...)
    where the programs write the thesis' symbols (ξ, ν, μ, θ, ...), its last line is not the one
    exit-status line, or an option's description is not indented apart from the option.

Python 3 standard library only; run by ctest as `docs.check`.
"""
import fnmatch
import os
import re
import subprocess
import sys
import tempfile

# An option line of the --help text written by lib/core/cli: "  -o, --output <FILE>" or
# "      --version"; descriptions follow on lines of their own.
HELP_OPTION = re.compile(r"^\s+(?:-[A-Za-z0-9],\s+)?--([a-z0-9][a-z0-9-]*)(?=\s|$)")
# A command line of a "Commands:" block: "  d2min    description".
HELP_COMMAND = re.compile(r"^  ([a-z][a-z0-9-]*)\s{2,}\S")
# A markdown link or image: [text](target) with an optional "title"; reference
# definitions "[label]: target" are read separately.
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE_LINK = re.compile(r"^\s{0,3}\[[^\]]+\]:\s+<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


def help_text(command):
    """The text `command --help` prints (command: the program, or the program and a command of it)."""
    shown = " ".join(os.path.basename(c) for c in command)
    try:
        result = subprocess.run(command + ["--help"], capture_output=True, text=True, timeout=60)
    except OSError as e:
        raise SystemExit(f"check_docs.py: cannot run '{shown} --help': {e}")
    if result.returncode != 0:
        raise SystemExit(f"check_docs.py: '{shown} --help' exited with {result.returncode}: {result.stderr.strip()}")
    return result.stdout


def help_commands(text):
    """The commands a --help text lists in its "Commands:" block ("  NAME   description" lines)."""
    names, inside = [], False
    for line in text.splitlines():
        if line.strip() == "Commands:":
            inside = True
            continue
        if inside:
            m = HELP_COMMAND.match(line)
            if m:
                names.append(m.group(1))
            elif not line.startswith("   "):
                inside = False
    return names


# Symbols spelled out where every --help writes the thesis' letter (an option's or a dataset's
# name, "--xi" or "xi_abs", is a name, not the symbol).
ASCII_SYMBOL = re.compile(
    r"(?<![-A-Za-z_/<|])(xi|nu|mu|theta|sigma|chi|omega|gamma|gammadot|tau|Phi|Psi|pi|kappa|zeta|D2min)(?![-\w|>])"
)
EXIT_STATUS = "Exit status: 0 success, 1 runtime failure or interruption, 2 bad usage or bad input."
DESCRIPTION_INDENT = 10


def help_style(program):
    """Problems of notation and layout in `program --help` and its commands' --help."""
    text = help_text([program])
    problems = []
    name = os.path.basename(program)
    for command, t in [(name, text)] + [(f"{name} {c}", help_text([program, c])) for c in help_commands(text)]:
        lines = t.rstrip("\n").splitlines()
        if not lines or lines[-1] != EXIT_STATUS:
            problems.append(f"{command} --help: its last line is not '{EXIT_STATUS}'")
        for k, line in enumerate(lines):
            m = ASCII_SYMBOL.search(line)
            if m:
                problems.append(f"{command} --help: '{m.group(1)}' spelled out in ASCII: {line.strip()}")
            if HELP_OPTION.match(line) and k + 1 < len(lines):
                below = lines[k + 1]
                if below.strip() and not HELP_OPTION.match(below) and len(below) - len(below.lstrip()) != DESCRIPTION_INDENT:
                    problems.append(f"{command} --help: the description of '{line.strip()}' is not indented "
                                    f"{DESCRIPTION_INDENT} columns")
    return problems


def help_options(program):
    """Long option names that `program --help` lists, in order, and those of each command it
    lists (`program COMMAND --help`), with the commands."""
    text = help_text([program])
    commands = help_commands(text)
    texts = [text] + [help_text([program, c]) for c in commands]
    names = []
    for t in texts:
        for line in t.splitlines():
            m = HELP_OPTION.match(line)
            if m and m.group(1) not in names:
                names.append(m.group(1))
    if not names:
        raise SystemExit(f"check_docs.py: '{program} --help' lists no option; is it a granflow program?")
    return names


def mentions(text, option):
    """Whether text names --option as a whole word (--time is not --time-step)."""
    return re.search(r"(?<![A-Za-z0-9-])--" + re.escape(option) + r"(?![A-Za-z0-9-])", text) is not None


def table_options(text):
    """Options named in the first cell of table rows, e.g. | `--seed` | ... or | `-o, --output` | ..."""
    found = []
    for line in text.splitlines():
        if not line.lstrip().startswith("|"):
            continue
        cells = line.strip().strip("|").split("|")
        if not cells:
            continue
        for name in re.findall(r"(?<![A-Za-z0-9-])--([a-z0-9][a-z0-9-]*)", cells[0]):
            found.append(name)
    return found


CODE_SPAN = re.compile(r"(`+)((?:(?!\1).)+?)\1")


def prose_lines(text):
    """Each line of text, or "" for a line of a fenced code block or its fences."""
    out, fence = [], None
    for line in text.splitlines():
        stripped = line.lstrip()
        if fence is None and (stripped.startswith("```") or stripped.startswith("~~~")):
            fence = stripped[:3]
            out.append("")
            continue
        if fence is not None:
            if stripped.startswith(fence):
                fence = None
            out.append("")
            continue
        out.append(line)
    return out


def strip_code(text):
    """Text with fenced code blocks and inline code spans blanked (links there are not links)."""
    return [CODE_SPAN.sub(lambda m: " " * len(m.group(0)), line) for line in prose_lines(text)]


def slug(heading, seen):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens,
    -1, -2, ... appended to repeats."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # links keep their text
    text = re.sub(r"<[^>]+>", "", text)
    s = re.sub(r"[^\w\- ]", "", text.lower()).replace(" ", "-")
    n = seen.get(s, 0)
    seen[s] = n + 1
    return s if n == 0 else f"{s}-{n}"


def anchors(path, cache={}):
    if path not in cache:
        seen, found = {}, set()
        with open(path, encoding="utf-8") as f:
            for line in strip_code(f.read()):
                m = HEADING.match(line)
                if m:
                    found.add(slug(m.group(2), seen))
        # Explicit anchors <a id="..."> / <a name="...">.
        with open(path, encoding="utf-8") as f:
            found.update(re.findall(r"<a\s+(?:id|name)=\"([^\"]+)\"", f.read()))
        cache[path] = found
    return cache[path]


def markdown_files(root):
    files = [
        os.path.join(root, name) for name in ("README.md", "CHANGELOG.md") if os.path.isfile(os.path.join(root, name))
    ]
    docs = os.path.join(root, "docs")
    for directory, _, names in sorted(os.walk(docs)):
        files += [os.path.join(directory, n) for n in sorted(names) if n.endswith(".md")]
    return files


def check_links(root, path):
    problems, count = [], 0
    rel = os.path.relpath(path, root)
    with open(path, encoding="utf-8") as f:
        lines = strip_code(f.read())
    for number, line in enumerate(lines, 1):
        targets = INLINE_LINK.findall(line)
        m = REFERENCE_LINK.match(line)
        if m:
            targets.append(m.group(1))
        for target in targets:
            if SCHEME.match(target) or target.startswith("//"):
                continue  # external: not checked here
            count += 1
            file_part, _, anchor = target.partition("#")
            if file_part:
                resolved = os.path.normpath(os.path.join(os.path.dirname(path), file_part))
                if not os.path.exists(resolved):
                    problems.append(
                        f"{rel}:{number}: link '{target}' points nowhere "
                        f"({os.path.relpath(resolved, root)} does not exist)"
                    )
                    continue
                if not os.path.realpath(resolved).startswith(os.path.realpath(root) + os.sep):
                    problems.append(f"{rel}:{number}: link '{target}' leaves the repository")
                    continue
            else:
                resolved = path
            if anchor and resolved.endswith(".md") and os.path.isfile(resolved):
                if anchor not in anchors(resolved):
                    problems.append(
                        f"{rel}:{number}: link '{target}': {os.path.relpath(resolved, root)} "
                        f"has no heading with anchor '#{anchor}'"
                    )
    return problems, count


# A glob or a placeholder: `lib/dynamics/lemke.*`, `lib/{io,core}`, `<run>/x`, `$(BUILD)/bin`.
NOT_A_PATH = re.compile(r"[*?\[\]{}<>$]")


def ignored_dirs(root):
    """The directory patterns of root/.gitignore ("/build*/", "*.egg-info/"): outputs."""
    with open(os.path.join(root, ".gitignore"), encoding="utf-8") as f:
        return [line.strip() for line in f if line.strip().endswith("/") and not line.startswith(("#", "!"))]


def is_output(quoted, patterns):
    """Whether a repository path lies in a directory that one of .gitignore's patterns ignores."""
    parts = quoted.rstrip("/").split("/")
    for k in range(1, len(parts) + 1):
        for pattern in patterns:
            if pattern.startswith("/") and fnmatch.fnmatchcase("/".join(parts[:k]), pattern.strip("/")):
                return True
            if not pattern.startswith("/") and fnmatch.fnmatchcase(parts[k - 1], pattern.strip("/")):
                return True
    return False


def source_dirs(root, patterns):
    """The top-level directories of root that quoted repository paths start with."""
    return {
        n for n in os.listdir(root)
        if os.path.isdir(os.path.join(root, n)) and n != ".git" and not is_output(n, patterns)
    }


def quoted_paths(line, dirs, patterns):
    """The repository paths quoted in a line's inline code spans (the rule of the docstring)."""
    for span in CODE_SPAN.finditer(line):
        for token in span.group(2).split():
            token = re.split(r"[:#]", token.strip("'\"()[],;"), maxsplit=1)[0]
            if "/" in token and not NOT_A_PATH.search(token) and token.split("/", 1)[0] in dirs:
                if not is_output(token, patterns):
                    yield token


def check_paths(root, path, dirs, patterns):
    """Problems with the repository paths a markdown file quotes, and how many it quotes."""
    problems, count = [], 0
    rel = os.path.relpath(path, root)
    with open(path, encoding="utf-8") as f:
        lines = prose_lines(f.read())
    for number, line in enumerate(lines, 1):
        for quoted in quoted_paths(line, dirs, patterns):
            count += 1
            if not os.path.exists(os.path.join(root, quoted)):
                problems.append(f"{rel}:{number}: quoted path '{quoted}' does not exist in the tree")
    return problems, count


def check_paths_self_test(root, dirs, patterns):
    """Problems if the quoted-path check misses a planted dangling path, or flags what its rule
    leaves out (an output, a glob, an assignment, a fenced block)."""
    planted = "lib/no_such_dir/planted.hpp"
    text = (
        f"Planted: `{planted}:12`, `runs/quick/x.h5`, `lib/*.hpp`, `-DX=lib/none`, `lib/`.\n"
        "```sh\ncat lib/no_such_dir/fenced.hpp\n```\n"
    )
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "planted.md")
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        found, count = check_paths(root, path, dirs, patterns)
    wanted = [f"{os.path.relpath(path, root)}:1: quoted path '{planted}' does not exist in the tree"]
    if found != wanted or count != 2:
        return [f"check_docs.py: the quoted-path check found {found} ({count} paths) in a planted page, not {wanted}"]
    return []


def check_version(root, bin_dir, programs):
    """Problems with the version's one place and its copies (docs/releases.md)."""
    problems = []
    with open(os.path.join(root, "CMakeLists.txt"), encoding="utf-8") as f:
        found = re.search(r"project\(granflow\s+VERSION\s+(\d+\.\d+\.\d+)", f.read())
    if not found:
        return ["CMakeLists.txt: no project(granflow VERSION x.y.z)"]
    version = found.group(1)
    with open(os.path.join(root, "CITATION.cff"), encoding="utf-8") as f:
        cited = re.findall(r"^\s*version:\s*\"?([^\s\"]+)", f.read(), re.M)
    if not cited or any(v != version for v in cited):
        problems.append(f"CITATION.cff: version {cited} is not CMakeLists.txt's {version}")
    with open(os.path.join(root, "CHANGELOG.md"), encoding="utf-8") as f:
        sections = re.findall(r"^## (\S+)", f.read(), re.M)
    numbered = [s for s in sections if re.fullmatch(r"\d+\.\d+\.\d+", s)]
    if version not in numbered and not (sections and sections[0] == "Unreleased"):
        problems.append(f"CHANGELOG.md: no section '## {version}' (nor '## Unreleased' first)")
    with open(os.path.join(root, "LICENSE"), encoding="utf-8") as f:
        if not f.readline().startswith("BSD 3-Clause License"):
            problems.append("LICENSE: not the BSD 3-Clause licence the programs name")
    for program in programs:
        out = subprocess.run([os.path.join(bin_dir, program), "--version"], capture_output=True, text=True).stdout
        lines = out.splitlines()
        if not lines or not lines[0].startswith(f"{program} {version} ("):
            problems.append(f"{program} --version: first line {lines[:1]} is not '{program} {version} (<commit>)'")
        if "BSD-3-Clause" not in out:
            problems.append(f"{program} --version: does not name the licence (BSD-3-Clause)")
    return problems


def main():
    if len(sys.argv) != 3:
        raise SystemExit("usage: check_docs.py REPO_ROOT BIN_DIR")
    root, bin_dir = (os.path.abspath(a) for a in sys.argv[1:])
    problems = []

    programs = sorted(
        n for n in os.listdir(bin_dir) if n.startswith("gf-") and os.access(os.path.join(bin_dir, n), os.X_OK)
    )
    if not programs:
        raise SystemExit(f"check_docs.py: no gf-* program in {bin_dir}")
    pages_dir = os.path.join(root, "docs", "programs")
    options_checked = 0
    for program in programs:
        page = os.path.join(pages_dir, program + ".md")
        rel = os.path.relpath(page, root)
        listed = help_options(os.path.join(bin_dir, program))
        if not os.path.isfile(page):
            problems.append(f"{program}: has no page {rel}")
            continue
        with open(page, encoding="utf-8") as f:
            text = f.read()
        for option in listed:
            options_checked += 1
            if not mentions(text, option):
                problems.append(f"{rel}: does not mention option --{option}, which `{program} --help` lists")
        for option in table_options(text):
            if option not in listed:
                problems.append(f"{rel}: its option table has --{option}, which `{program} --help` does not list")
    if os.path.isdir(pages_dir):
        for name in sorted(os.listdir(pages_dir)):
            if name.startswith("gf-") and name.endswith(".md") and name[:-3] not in programs:
                problems.append(f"docs/programs/{name}: no program {name[:-3]} in {bin_dir}")

    problems += check_version(root, bin_dir, programs)
    for program in programs:
        problems += help_style(os.path.join(bin_dir, program))

    links_checked = 0
    files = markdown_files(root)
    for path in files:
        found, count = check_links(root, path)
        problems += found
        links_checked += count

    paths_checked = 0
    patterns = ignored_dirs(root)
    dirs = source_dirs(root, patterns)
    problems += check_paths_self_test(root, dirs, patterns)
    for path in files:
        if path != os.path.join(root, "CHANGELOG.md"):
            found, count = check_paths(root, path, dirs, patterns)
            problems += found
            paths_checked += count

    for p in problems:
        print(p)
    summary = (
        f"{len(programs)} programs, {options_checked} options, {len(files)} markdown files, "
        f"{links_checked} relative links, {paths_checked} quoted repository paths checked"
    )
    if problems:
        print(f"check_docs.py: FAILED: {len(problems)} problem(s); {summary}")
        return 1
    print(f"check_docs.py: OK: {summary}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
