#!/usr/bin/env python3
"""The house function-size check: clang-tidy's readability-function-size, 120 lines, over the project's
C++ files, against one list of exceptions that may only shrink (tests/tools/function_size_exceptions.txt).

It fails when a function not listed exceeds the threshold, when a listed one grew past its listed length,
and when a listed one no longer exceeds it or no longer exists (remove its line). Functions are named by
file and clang-tidy's (unqualified) name.

By default it checks the files changed on this branch: those that differ from the merge base with the first
of $PLEAT_SIZE_BASE, origin/main, main that exists (the files of the last commit when that is HEAD itself),
and uncommitted ones. --all checks every file (about 6 s a file on one core), as scripts/check_tidy.sh
does. Files may also be named. Uses BUILD_DIR/compile_commands.json without GCC's precompiled headers. A
function's length depends on its file's text alone, so what a file gave is kept in BUILD_DIR/function_size/
by the file's hash, and a file unchanged since is not parsed again.

Usage: check_function_size.py SOURCE_DIR BUILD_DIR [--all | FILE...] [--jobs N]
"""
import hashlib
import json
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

THRESHOLD = 120
MODULES = ("support", "cli", "sim_io", "static_core", "kinetic", "shading")
EXCEPTIONS = "tests/tools/function_size_exceptions.txt"


def git(source, *args):
    result = subprocess.run(["git", "-C", source, *args], capture_output=True, text=True)
    return result.stdout.strip() if result.returncode == 0 else None


def in_modules(path):
    return path.endswith(".cpp") and path.split("/", 1)[0] in MODULES


def changed_files(source):
    """The module .cpp files changed on this branch (see the module comment), relative to `source`."""
    refs = [os.environ.get("PLEAT_SIZE_BASE"), "origin/main", "main"]
    head = git(source, "rev-parse", "HEAD")
    base = None
    for ref in filter(None, refs):
        base = git(source, "merge-base", "HEAD", ref)
        if base:
            break
    if head is None:
        return None
    if base is None or base == head:
        base = git(source, "rev-parse", "HEAD~1") or head
    names = set()
    for args in (("diff", "--name-only", base, "HEAD"), ("diff", "--name-only", "HEAD"),
                 ("ls-files", "--others", "--exclude-standard")):
        out = git(source, *args)
        names.update(line for line in (out or "").splitlines() if line)
    return sorted(n for n in names if in_modules(n) and os.path.exists(os.path.join(source, n)))


def all_files(source):
    out = git(source, "ls-files", "*.cpp")
    if out is None:
        files = []
        for module in MODULES:
            for root, _, names in os.walk(os.path.join(source, module)):
                files += [os.path.relpath(os.path.join(root, n), source) for n in names]
        return sorted(f for f in files if in_modules(f))
    return sorted(f for f in out.splitlines() if in_modules(f))


def compile_database(source, build):
    """BUILD_DIR/function_size/compile_commands.json: the build's, without GCC's precompiled headers (which
    clang cannot read). Returns its directory and the set of files it compiles (relative to `source`)."""
    with open(os.path.join(build, "compile_commands.json")) as f:
        entries = json.load(f)
    known = set()
    for e in entries:
        e["command"] = re.sub(r" -include \S+cmake_pch\.hxx", "", e["command"]).replace(" -Winvalid-pch", "")
        known.add(os.path.relpath(e["file"], source))
    out = os.path.join(build, "function_size")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "compile_commands.json"), "w") as f:
        json.dump(entries, f)
    return out, known


WARNING = re.compile(r"^(.*?):(\d+):\d+: warning: function '([^']+)' exceeds recommended size")
NOTE = re.compile(r"^.*?:\d+:\d+: note: (\d+) lines including whitespace and comments")


def offenders(source, database, path):
    """[(function, lines)] of the file `path` (relative to `source`) over the threshold."""
    config = "{CheckOptions: [{key: readability-function-size.LineThreshold, value: %d}]}" % THRESHOLD
    result = subprocess.run(["clang-tidy", "-p", database, "--quiet", "--checks=-*,readability-function-size",
                             "--config=" + config, os.path.join(source, path)],
                            capture_output=True, text=True)
    found, name = [], None
    for line in result.stdout.splitlines():
        m = WARNING.match(line)
        if m:
            name = m.group(3) if os.path.realpath(m.group(1)) == os.path.realpath(os.path.join(source, path)) else None
            continue
        m = NOTE.match(line)
        if m and name:
            found.append((name, int(m.group(1))))
            name = None
    if result.returncode != 0 and not found and "error:" in result.stdout + result.stderr:
        raise RuntimeError("clang-tidy failed on %s:\n%s%s" % (path, result.stdout, result.stderr))
    return found


def read_exceptions(source):
    """{(file, function): lines} of the exceptions file; raises on a malformed or repeated line."""
    listed = {}
    with open(os.path.join(source, EXCEPTIONS)) as f:
        for number, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            parts = line.split()
            if len(parts) != 3 or not parts[2].isdigit():
                raise ValueError("%s:%d: expected 'FILE FUNCTION LINES'" % (EXCEPTIONS, number))
            key = (parts[0], parts[1])
            if key in listed:
                raise ValueError("%s:%d: %s %s listed twice" % (EXCEPTIONS, number, *key))
            listed[key] = int(parts[2])
    return listed


def main(argv):
    args, files, jobs, check_all = [], [], os.cpu_count() or 2, False
    i = 0
    while i < len(argv):
        if argv[i] == "--all":
            check_all = True
        elif argv[i] == "--jobs":
            i += 1
            jobs = int(argv[i])
        else:
            args.append(argv[i])
        i += 1
    if len(args) < 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    source, build = os.path.abspath(args[0]), os.path.abspath(args[1])
    files = [os.path.relpath(os.path.abspath(f), source) for f in args[2:]]
    try:
        listed = read_exceptions(source)
    except (OSError, ValueError) as e:
        print("check_function_size: %s" % e, file=sys.stderr)
        return 2
    if check_all:
        files = all_files(source)
    elif not files:
        files = changed_files(source)
        if files is None:
            print("check_function_size: not a git checkout; name the files or pass --all", file=sys.stderr)
            return 2
    problems = []
    for (path, function) in listed:
        if not os.path.exists(os.path.join(source, path)):
            problems.append("%s: listed in %s but gone: remove its line" % (path, EXCEPTIONS))
    database, known = compile_database(source, build)
    files = [f for f in files if f in known]  # a file this configuration does not build (MPI) is not checked
    cache_path = os.path.join(database, "results.json")
    try:
        with open(cache_path) as f:
            cache = json.load(f)
    except (OSError, ValueError):
        cache = {}

    def file_hash(path):
        with open(os.path.join(source, path), "rb") as f:
            return hashlib.sha256(f.read() + b"%d" % THRESHOLD).hexdigest()

    def check(path):
        digest = file_hash(path)
        kept = cache.get(path)
        if kept and kept.get("hash") == digest:
            return path, [tuple(o) for o in kept["offenders"]]
        found = offenders(source, database, path)
        cache[path] = {"hash": digest, "offenders": found}
        return path, found

    with ThreadPoolExecutor(max_workers=max(jobs, 1)) as pool:
        results = list(pool.map(check, files))
    with open(cache_path + ".tmp", "w") as f:
        json.dump(cache, f)
    os.replace(cache_path + ".tmp", cache_path)
    for path, found in results:
        names = {name for name, _ in found}
        for name, lines in found:
            allowed = listed.get((path, name))
            if allowed is None:
                problems.append("%s: %s() is %d lines, over %d: cut it along its steps" % (path, name, lines, THRESHOLD))
            elif lines > allowed:
                problems.append("%s: %s() grew to %d lines (listed at %d in %s): cut it, do not raise the entry"
                                % (path, name, lines, allowed, EXCEPTIONS))
        for (listed_path, name), allowed in listed.items():
            if listed_path == path and name not in names:
                problems.append("%s: %s() is no longer over %d lines (or gone): remove its line from %s"
                                % (path, name, THRESHOLD, EXCEPTIONS))
    for p in problems:
        print("check_function_size: " + p, file=sys.stderr)
    print("check_function_size: %d file(s) checked, %d exception(s) listed, %d problem(s)"
          % (len(files), len(listed), len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
