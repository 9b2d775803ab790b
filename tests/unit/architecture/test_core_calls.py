"""The C core's files call one way: no function of one file calls a function of a second file that
calls back into the first (issue 42). Read from the source: each file's external function
definitions (at brace depth 0, not static) and the names it calls; a call counts for the file
whose definition it names. Functions a header defines (static inline) count for the header."""

from __future__ import annotations

import re
from collections import defaultdict
from pathlib import Path

from railbrake._layers import cycles

SOURCES = Path(__file__).resolve().parents[3] / "core" / "src"
_COMMENTS = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)
_LITERALS = re.compile(r'"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'')
_DIRECTIVES = re.compile(r"^[ \t]*#(?:[^\n]*\\\n)*[^\n]*", re.M)
_CALL = re.compile(r"\b([A-Za-z_]\w*)\s*\(")
_KEYWORDS = {"if", "for", "while", "switch", "return", "sizeof", "defined", "__attribute__", "target"}


def _clean(text: str) -> str:
    return _DIRECTIVES.sub("", _LITERALS.sub('""', _COMMENTS.sub(" ", text)))


def _top_level(text: str) -> list[tuple[str, str]]:
    """(the text before a depth-0 brace, the body it opens) for each block of the file."""
    blocks, depth, start, head_start = [], 0, 0, 0
    for i, ch in enumerate(text):
        if ch == "{":
            if depth == 0:
                start = i
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                blocks.append((text[head_start:start], text[start:i + 1]))
                head_start = i + 1
        elif ch == ";" and depth == 0:
            head_start = i + 1
    return blocks


def _definitions(text: str) -> list[tuple[str, bool, str]]:
    """(name, static, body) of each function defined in the file."""
    found = []
    for head, body in _top_level(text):
        match = re.search(r"\b([A-Za-z_]\w*)\s*\([^()]*(?:\([^()]*\)[^()]*)*\)\s*$", head)
        if match and not re.search(r"\b(struct|union|enum)\s+\w*\s*$", head) and "=" not in head:
            found.append((match.group(1), bool(re.search(r"\bstatic\b", head)), body))
    return found


def call_graph(sources: Path = SOURCES) -> dict[str, dict[str, set[str]]]:
    """file -> {file it calls: the functions called there}."""
    texts = {p.name: _clean(p.read_text()) for p in sorted(sources.glob("*.[ch]"))}
    owner = {}
    for name, text in texts.items():
        for function, static, _ in _definitions(text):
            if not static or name.endswith(".h"):
                owner[function] = name
    calls: dict[str, dict[str, set[str]]] = defaultdict(lambda: defaultdict(set))
    for name, text in texts.items():
        for _, _, body in _definitions(text):
            for called in _CALL.findall(body):
                target = owner.get(called)
                if called not in _KEYWORDS and target is not None and target != name:
                    calls[name][target].add(called)
    return calls


def test_the_parse_finds_the_cores_functions():
    graph = call_graph()
    assert "rb_plant_step" in {f for targets in graph.values() for names in targets.values() for f in names}
    assert graph["run.c"], "run.c calls into the plant and the BCU"


def test_no_core_file_calls_back_into_a_file_that_calls_it():
    graph = call_graph()
    back = [f"{a} calls {sorted(graph[a][b])} of {b}, which calls {sorted(graph[b][a])} of {a}"
            for a in sorted(graph) for b in sorted(graph[a]) if a < b and a in graph.get(b, {})]
    assert not back, "\n".join(back)


def test_no_longer_circle_of_calls_between_core_files():
    graph = call_graph()
    assert not cycles({a: set(targets) for a, targets in graph.items()})


def test_the_check_sees_a_call_back(tmp_path):
    (tmp_path / "a.c").write_text('/* a */\n#include "x.h"\nstatic int helper(void) { return 1; }\n'
                                  'int rb_a(int x)\n{\n    return rb_b(x) + helper(); /* rb_c( in a comment */\n}\n')
    (tmp_path / "b.c").write_text('int rb_b(int x)\n{\n    const char *s = "rb_a(";\n    return x > 0 ? rb_a(x - 1) : 0;\n}\n'
                                  'static int rb_c(void) { return 0; }\n')
    graph = call_graph(tmp_path)
    assert {a: {b: sorted(n) for b, n in t.items()} for a, t in graph.items()} == \
        {"a.c": {"b.c": ["rb_b"]}, "b.c": {"a.c": ["rb_a"]}}
    assert cycles({a: set(t) for a, t in graph.items()}) == [["a.c", "b.c"]]
