"""One home for every word a student reads about the queue and control: `melfa.vocab.queue`
and `melfa.vocab.lease`. The browser reads them from ``/vocab.js`` (``QUEUE_WORDS``,
``CONTROL_WORDS``, ``HOLDER_STATES`` beside the steps and reasons), the desktop client
imports them. Each test below fails on a second copy and names where it is:

- a word of these families written again in a script, a page or a Python module;
- a sentence written into a script that speaks only through ``/vocab.js`` (the queue's,
  control's, the desk's, the class view's …) instead of read from the vocabulary;
- a word a script asks the vocabulary for that it does not have (it would show
  ``undefined``).
"""

from __future__ import annotations

import ast
import dataclasses
import json
import re
from collections.abc import Iterator
from pathlib import Path

import pytest

from melfa.protocol.advice import FIX_LABELS, Fix
from melfa.vocab.lease import CONTROL_WORDS, HolderState, LeaseReason
from melfa.vocab.queue import QUEUE_WORDS, EntryState, QueueStep
from melfa.web.routes.vocab import vocab_module, vocabulary

SRC = Path(__file__).resolve().parents[2] / "src" / "melfa"
STATIC = SRC / "web" / "static"

SPEAKS_ONLY_VOCAB = (
    *("queue.js", "control.js", "slot.js", "signout.js", "startopts.js", "assign.js"),
    *("desk.js", "classview.js"),
)
"""The scripts whose every word comes from /vocab.js: no sentence in them."""


def _words() -> dict[str, str]:
    """Every word of the queue's and control's families, named by where it lives."""
    words = {f"QUEUE_WORDS.{k}": v for k, v in dataclasses.asdict(QUEUE_WORDS).items()}
    words |= {f"CONTROL_WORDS.{k}": v for k, v in dataclasses.asdict(CONTROL_WORDS).items()}
    words |= {f"QueueStep.{s.name}": s.template for s in QueueStep}
    words |= {f"EntryState.{e.name}": e.words for e in EntryState}
    words |= {f"LeaseReason.{r.name}": r.template for r in LeaseReason}
    words |= {f"HolderState.{h.name}": h.words for h in HolderState}
    return words


def _pieces(template: str) -> Iterator[str]:
    """The fixed text of a template between its ``{placeholders}``: what a copy would
    repeat word for word."""
    for piece in re.split(r"\{\w+\}", template):
        piece = piece.strip(" .:;,()·—")
        if piece:
            yield piece


def _sentences() -> dict[str, str]:
    """The pieces a copy would give away: three words or more, or a label of two ("Take
    control"). A single word such as "away", or two common ones ("the instructor"), is
    checked where it would be shown (`test_the_scripts_that_speak_vocab_write_no_sentence`)."""
    return {
        p: name
        for name, t in _words().items()
        for p in _pieces(t)
        if p.count(" ") >= 2 or (p.count(" ") == 1 and p[0].isupper())
    }


_STRING = re.compile(r""""(?:[^"\\\n]|\\.)*"|'(?:[^'\\\n]|\\.)*'|`(?:[^`\\]|\\.)*`""")


def _code(path: Path) -> str:
    """A script's or page's text without its comments (prose may name a word), its lines
    where they were."""
    text = path.read_text(encoding="utf-8")
    lines_kept = lambda m: "\n" * m.group().count("\n")  # noqa: E731
    if path.suffix == ".html":
        return re.sub(r"<!--.*?-->", lines_kept, text, flags=re.S)
    text = re.sub(r"/\*.*?\*/", lines_kept, text, flags=re.S)
    return re.sub(r"(^|\s)//.*", r"\1", text, flags=re.M)


def _literals(path: Path) -> Iterator[tuple[int, str]]:
    """(line, text) of each string literal of a script; a template's ``${…}`` left out,
    and a literal a code is compared with or set as (``state !== "connected"``)."""
    code = _code(path)
    for match in _STRING.finditer(code):
        if re.search(r"([!=]==?|dataset\.\w+ =)\s*$", code[: match.start()]) or re.match(
            r"\s*[!=]==?", code[match.end() :]
        ):
            continue
        text = re.sub(r"\$\{[^}]*\}", "{}", match.group()[1:-1])
        yield code.count("\n", 0, match.start()) + 1, text


def _python_strings(path: Path) -> Iterator[tuple[int, str]]:
    """(line, text) of each string constant of a module, docstrings left out."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docs = {id(node.value) for node in ast.walk(tree) if isinstance(node, ast.Expr)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
            yield node.lineno, node.value


def _scripts() -> list[Path]:
    return sorted((STATIC / "js").glob("*.js"))


def test_the_queue_and_control_words_are_served() -> None:
    served = re.findall(r"export const (\w+) = (.*);", vocab_module())
    tables = {name: json.loads(table) for name, table in served}
    assert tables["QUEUE_WORDS"] == dataclasses.asdict(QUEUE_WORDS)
    assert tables["CONTROL_WORDS"] == dataclasses.asdict(CONTROL_WORDS)
    assert tables["HOLDER_STATES"] == {h.value: h.words for h in HolderState}
    assert tables["QUEUE_WORDS"]["leave"] == "Leave the queue"


def test_no_queue_or_control_word_is_written_twice() -> None:
    """ "Leave the queue" in a script, a page or the desktop client is a second copy: read
    ``QUEUE_WORDS.leave`` instead."""
    sentences = _sentences()
    assert {"Leave the queue", "Take control", "the arm is offered to"} <= set(sentences)
    found = []
    for path in [*_scripts(), *sorted(STATIC.glob("*.html"))]:
        texts = _literals(path) if path.suffix == ".js" else enumerate(_code(path).splitlines(), 1)
        for line, text in texts:
            found += [
                f"{path.relative_to(SRC)}:{line}: {piece!r} is {name}"
                for piece, name in sentences.items()
                if piece in text
            ]
    for path in sorted((SRC / "desktop").glob("*.py")):  # the client that shows them too
        for line, text in _python_strings(path):
            found += [
                f"{path.relative_to(SRC)}:{line}: {piece!r} is {name}"
                for piece, name in sentences.items()
                if piece in text
            ]
    assert not found, "written again (read it from melfa.vocab):\n" + "\n".join(found)


def _css_classes() -> set[str]:
    css = "".join(p.read_text(encoding="utf-8") for p in (STATIC / "css").glob("*.css"))
    return set(re.findall(r"\.([a-z][\w-]*)", css))


def _reads_as_words(text: str, classes: set[str], words: set[str]) -> bool:
    """Whether a literal is something a person reads, not code: a path, an HTTP method, a
    single lowercase token (a code, id, event or tag) that is no word of the vocabulary,
    lowercase tokens between commas or a slash (a CSV file's header row, a MIME type), or a
    list of CSS classes are code; anything else with a letter in it is words."""
    bare = re.sub(r"\{\w*\}|\\.", "", text)  # placeholders and escapes
    if not re.search(r"[A-Za-z]", bare) or bare.startswith(("/", "./", ".", "#")):
        return False  # a path or a selector
    if bare in ("GET", "POST", "PUT", "DELETE") or re.fullmatch(r"[A-Z]+\d+", bare):
        return False  # an HTTP method, a controller's name (FL1)
    if re.fullmatch(r"[a-z0-9_.-]+", bare.strip()):
        return text in words
    if re.fullmatch(r"[a-z0-9_.-]+(,[a-z0-9_.-]+)+|[a-z]+/[a-z0-9.+-]+", bare):
        return False  # "username,password\n" heads a CSV file, "text/csv" is its type
    tokens = text.split()
    return not (tokens and all(t in classes for t in tokens))


@pytest.mark.parametrize("name", SPEAKS_ONLY_VOCAB)
def test_the_scripts_that_speak_vocab_write_no_sentence(name: str) -> None:
    """``el("span", {}, "away")`` or ``toast("Your turn ends soon")`` in these scripts is a
    word that skipped the vocabulary: add it to `melfa.vocab` and read it from /vocab.js."""
    classes = _css_classes()
    words = {w for t in vocabulary().values() for w in _all_strings(t)} - classes
    path = STATIC / "js" / name
    found = [
        f"{name}:{line}: {text!r}"
        for line, text in _literals(path)
        if _reads_as_words(text, classes, words)
    ]
    assert not found, "words written in the script:\n" + "\n".join(found)


def _all_strings(table: object) -> Iterator[str]:
    if isinstance(table, str):
        yield table
    elif isinstance(table, dict):
        for value in table.values():
            yield from _all_strings(value)


def test_every_word_a_script_asks_for_is_served() -> None:
    """``W.leave`` where ``W`` is ``QUEUE_WORDS`` must be a key of it (a typo shows
    "undefined" to the student)."""
    tables = vocabulary()
    missing = []
    for path in _scripts():
        code = _code(path)
        for block in re.findall(r"import \{([^}]*)\} from \"/vocab\.js\"", code):
            for item in block.split(","):
                family, _, alias = (p.strip() for p in item.strip().partition(" as "))
                if not family:
                    continue
                table = tables[family]
                alias = alias or family
                if not isinstance(table, dict):
                    continue
                asked = re.findall(rf"\b{alias}\.(\w+)", code)
                asked += re.findall(rf"\b{alias}\[\"([^\"]+)\"\]", code)
                missing += [f"{path.name}: {family}.{k}" for k in asked if k not in table]
    assert not missing, "asked of /vocab.js but not there:\n" + "\n".join(missing)


def test_the_refusals_take_control_is_the_headers() -> None:
    """A refusal's one-click fix (`melfa.protocol.advice`) and the header's button say the
    same "Take control": protocol and vocab cannot import each other, so the two are held
    together here."""
    assert FIX_LABELS[Fix.TAKE_CONTROL] == CONTROL_WORDS.take
