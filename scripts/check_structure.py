#!/usr/bin/python3
"""The structure bars of the code base (the engine as named parts): no function or lambda in pkg/ or
app/ over 120 lines, no source file in pkg/ over 600 lines, py/yade_mss/__init__.py at most 150 lines.
Prints the longest functions; exit status 1 when a bar is broken. Run from the repository root."""
import glob
import re
import sys

CONTROL = re.compile(r'^\s*(?:\}\s*)?(if|for|while|switch|catch|do|else|try|namespace|struct|class|enum|union)\b')


def functions(path):
    """(name, lines) of every function or lambda body: a brace block whose statement before '{' has a ')'."""
    text = open(path).read()
    text = re.sub(r'//[^\n]*', '', text)
    text = re.sub(r'/\*.*?\*/', lambda m: '\n' * m.group(0).count('\n'), text, flags=re.S)
    text = re.sub(r'"(?:\\.|[^"\\\n])*"', '""', text)
    text = re.sub(r"'(?:\\.|[^'\\\n])'", "''", text)
    out, stack, line, stmt = [], [], 1, ''
    for ch in text:
        if ch == '\n':
            line += 1
        if ch == '{':
            head = stmt.strip()
            is_fn = ')' in head and not CONTROL.match(head.split('\n')[-1] if head else '') and not head.endswith('=')
            stack.append((line, is_fn, head.split('(')[0].split()[-1] if is_fn and head.split('(')[0].split() else '?'))
            stmt = ''
        elif ch == '}':
            if stack:
                start, is_fn, name = stack.pop()
                if is_fn:
                    out.append((name, line - start + 1, start))
            stmt = ''
        elif ch == ';':
            stmt = ''
        else:
            stmt += ch
    return out


def main():
    bad = []
    rows = []
    for path in sorted(glob.glob('pkg/**/*.[ch]pp', recursive=True) + glob.glob('app/*.cpp')):
        for name, n, start in functions(path):
            rows.append((n, '%s:%d %s' % (path, start, name)))
            if n > 120:
                bad.append('%s:%d: %s is %d lines (bar 120)' % (path, start, name, n))
        if path.startswith('pkg/') and path.endswith('.cpp'):
            n = sum(1 for _ in open(path))
            if n > 600:
                bad.append('%s: %d lines (bar 600)' % (path, n))
    n = sum(1 for _ in open('py/yade_mss/__init__.py'))
    if n > 150:
        bad.append('py/yade_mss/__init__.py: %d lines (bar 150)' % n)
    rows.sort(reverse=True)
    print('longest functions:')
    for n, where in rows[:8]:
        print('  %4d %s' % (n, where))
    for b in bad:
        print('BAR BROKEN: ' + b)
    print('structure: %d functions, %d bars broken' % (len(rows), len(bad)))
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
