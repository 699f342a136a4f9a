"""One home for every word a student reads about the queue and control: `melfa.vocab.queue`
and `melfa.vocab.lease`. The browser reads them from ``/vocab.js`` (``QUEUE_WORDS``,
``CONTROL_WORDS``, ``HOLDER_STATES`` beside the steps and reasons), the desktop client
imports them. Each test below fails on a second copy and names where it is:

- a word of these families written again in a script, a page or a Python module;
- a word of the IDE's (`melfa.vocab.ide`) or the first-run guide's (`melfa.vocab.guide`)
  written again anywhere;
- a sentence or a word written into any script (every script but those in
  `NOT_YET_IN_VOCAB`, whose words are still to move) instead of read from the vocabulary;
- a word a script asks the vocabulary for that it does not have (it would show
  ``undefined``).
"""

from __future__ import annotations

import ast
import dataclasses
import json
import re
from collections.abc import Iterator
from html.parser import HTMLParser
from pathlib import Path

import pytest

from melfa.protocol.advice import FIX_LABELS, Fix
from melfa.service.actors import Role as ActorRole
from melfa.store.models import Role as AccountRole
from melfa.vocab.account import ACCOUNT_WORDS
from melfa.vocab.guide import GUIDE_WORDS
from melfa.vocab.ide import IDE_WORDS
from melfa.vocab.lease import CONTROL_WORDS, HolderState, LeaseReason
from melfa.vocab.queue import QUEUE_WORDS, EntryState, QueueStep
from melfa.vocab.roles import ROLE_WORDS
from melfa.vocab.targets import TARGET_LABELS, TARGET_WORDS
from melfa.web.routes.vocab import vocab_module, vocabulary

SRC = Path(__file__).resolve().parents[2] / "src" / "melfa"
STATIC = SRC / "web" / "static"

NOT_YET_IN_VOCAB = frozenset(
    {
        *("api.js", "celleditor.js", "coedit-view.js", "debugger.js", "editor.js"),
        *("first.js", "jog.js", "melfa-mode.js", "opener.js"),
        *("points.js", "preflight.js", "replay.js", "switcher.js", "ui.js", "view3d.js"),
        *("workspace.js",),
    }
)
"""The scripts that still write words of their own (what remains to move into
`melfa.vocab`). Every other script, and every new one, takes each word it shows from
/vocab.js: `test_no_script_writes_a_word` names the file and line of one written there."""


def _words() -> dict[str, str]:
    """Every word of the queue's and control's families, named by where it lives."""
    words = {f"QUEUE_WORDS.{k}": v for k, v in dataclasses.asdict(QUEUE_WORDS).items()}
    words |= {f"CONTROL_WORDS.{k}": v for k, v in dataclasses.asdict(CONTROL_WORDS).items()}
    words |= {f"QueueStep.{s.name}": s.template for s in QueueStep}
    words |= {f"EntryState.{e.name}": e.words for e in EntryState}
    words |= {f"LeaseReason.{r.name}": r.template for r in LeaseReason}
    words |= {f"HolderState.{h.name}": h.words for h in HolderState}
    words |= {f"IDE_WORDS[{k!r}]": v for k, v in IDE_WORDS.items()}
    words |= {f"ACCOUNT_WORDS[{k!r}]": v for k, v in ACCOUNT_WORDS.items()}
    words |= {f"TARGET_WORDS[{k!r}]": v for k, v in TARGET_WORDS.items()}
    return words


def _pieces(template: str) -> Iterator[str]:
    """The fixed text of a template between its ``{placeholders}`` (and its ``**`` bold
    marks): what a copy would repeat word for word."""
    for piece in re.split(r"\{\w+\}|\*\*", template):  # ** marks bold (the guide)
        piece = piece.strip(" .:;,()·—")
        if piece:
            yield piece


def _sentences() -> dict[str, str]:
    """The pieces a copy would give away: three words or more, or a label of two ("Take
    control"). A single word such as "away", or two common ones ("the instructor"), is
    checked where it would be shown (`test_the_scripts_that_speak_vocab_write_no_sentence`)."""
    pieces = {
        p: name
        for name, t in _words().items()
        for p in _pieces(t)
        if p.count(" ") >= 2 or (p.count(" ") == 1 and p[0].isupper())
    }
    # The guide's, of three words or more: its titles ("Run it") are everyday phrases.
    for key, text in GUIDE_WORDS.items():
        pieces |= {p: f"GUIDE_WORDS[{key!r}]" for p in _pieces(text) if p.count(" ") >= 2}
    return pieces


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


def _reads_as_words(text: str, classes: set[str], words: set[str], shown: bool = True) -> bool:
    """Whether a literal is something a person reads, not code: a path, a CSS selector, an
    HTTP method, a single lowercase token (a code, id, event or tag; ``sim:``) that is no
    word of the vocabulary, lowercase tokens between commas or a slash (a CSV file's header
    row, a MIME type), a list of CSS classes, or text with no two letters in a row (a date's
    ``T00:00``) are code; anything else with a letter in it is words. A single lowercase
    word counts only where it is ``shown`` (it may be a code of the same spelling)."""
    bare = re.sub(r"\{\w*\}|\\.", "", text)  # placeholders and escapes
    if not re.search(r"[A-Za-z]{2}", bare) or bare.startswith(("/", "./", ".", "#")):
        return False  # a path or a selector
    if "://" in bare or re.search(r"\[[\w-]+(=[^\]]*)?\]|:not\(", bare):
        return False  # a selector: "button, [role=tab]", "button:not([disabled])"
    if bare in ("GET", "POST", "PUT", "DELETE") or re.fullmatch(r"[A-Z]+\d+", bare):
        return False  # an HTTP method, a controller's name (FL1)
    if re.fullmatch(r"[a-z0-9_.:-]+", bare.strip()):
        return shown and text in words
    if re.fullmatch(r"[a-z0-9_.-]+(,[a-z0-9_.-]+)+|[a-z]+/[a-z0-9.+-]+", bare):
        return False  # "username,password\n" heads a CSV file, "text/csv" is its type
    tokens = text.split()
    return not (tokens and all(_a_class(t, classes) for t in tokens))


def _a_class(token: str, classes: set[str]) -> bool:
    """A CSS class, or one of a family named by a placeholder (``target-{}``)."""
    if "{}" in token:
        stem = token.split("{}")[0]
        return bool(stem) and any(c.startswith(stem) for c in classes)
    return token in classes


_CODE_LIST = re.compile(r"""\[\s*(?:"[a-z0-9_.:-]+"\s*,\s*)+"[a-z0-9_.:-]+"\s*,?\s*\]""")
"""``["program", "load", "run"]``: a list of codes (steps, activities), not words."""


_SHOWN_ON = re.compile(
    r"""textContent\s*=|toast\(|showError\(|confirm\(|\b(title|placeholder)\s*[:=]|"aria-label"|\bel\("""
)
"""What, earlier on a literal's line, sends it to the screen: a node's text, a toast, a
tooltip, an element's children (``el("span", {}, "away")``)."""


def _shown(path: Path) -> Iterator[tuple[int, str, bool]]:
    """The literals of a script that may reach a person, and whether each is written where
    the screen shows it: a code the script compares with (``how === "done"``) is a code
    wherever it is written in it, so is each member of a list of codes; a programming
    error's message (``new TypeError(…)``, for the console) is not shown."""
    code = _code(path)
    codes = {m.group()[1:-1] for m in _STRING.finditer(code) if _compared(code, m)}
    for listed in _CODE_LIST.findall(code):
        codes |= {m.group()[1:-1] for m in _STRING.finditer(listed)}
    for match in _STRING.finditer(code):
        text = re.sub(r"\$\{[^}]*\}", "{}", match.group()[1:-1])
        before = code[code.rfind("\n", 0, match.start()) + 1 : match.start()]
        if _compared(code, match) or text in codes:
            continue
        if re.search(r"(new (Type|Range)Error\(|createComment\(|from|import\()\s*$", before):
            continue  # for the console, a comment in the page, a module's name
        if re.search(r"dataset\.\w+\s*=\s*$", before):
            continue  # a code the CSS or a test reads
        line = code.count("\n", 0, match.start()) + 1
        yield line, text, bool(_SHOWN_ON.search(before))


def _compared(code: str, match: re.Match[str]) -> bool:
    return bool(
        re.search(r"[!=]==?\s*$", code[: match.start()])
        or re.match(r"\s*[!=]==?", code[match.end() :])
    )


def _script_names() -> list[str]:
    return [path.name for path in _scripts()]


def _written(name: str) -> list[str]:
    """Each literal of the script ``name`` that reads as words, with its file and line."""
    classes = _css_classes()
    words = {w for t in vocabulary().values() for w in _all_strings(t)} - classes
    path = STATIC / "js" / name
    return [
        f"{path.relative_to(SRC)}:{line}: {text!r}"
        for line, text, shown in _shown(path)
        if _reads_as_words(text, classes, words, shown)
    ]


@pytest.mark.parametrize("name", [name for name in _script_names() if name not in NOT_YET_IN_VOCAB])
def test_no_script_writes_a_word(name: str) -> None:
    """``el("span", {}, "away")`` or ``toast("Your turn ends soon")`` in a script is a word
    that skipped the vocabulary: add it to `melfa.vocab` and read it from /vocab.js. Only
    the scripts in `NOT_YET_IN_VOCAB` still may (the next test holds that list to what is
    true)."""
    found = _written(name)
    assert not found, "words written in the script (read them from /vocab.js):\n" + "\n".join(found)


def test_the_scripts_still_to_move_still_write_words() -> None:
    """A script renamed or cleaned leaves `NOT_YET_IN_VOCAB` (and is held to the rule from
    then on): the list only shrinks."""
    assert set(_script_names()) >= NOT_YET_IN_VOCAB
    cleaned = sorted(name for name in NOT_YET_IN_VOCAB if not _written(name))
    assert not cleaned, f"no words of their own any more: take them off NOT_YET_IN_VOCAB {cleaned}"


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


def test_every_role_has_its_name() -> None:
    """The desk, the user menu, the header and the desktop client show a role's name, never
    its code: every role of the accounts (`melfa.store`) and of the service's actors has
    one, served as ``ROLE_WORDS``."""
    codes = {r.value for r in AccountRole} | {r.value for r in ActorRole}
    assert codes == set(ROLE_WORDS)
    assert all(words != code for code, words in ROLE_WORDS.items())
    assert vocabulary()["ROLE_WORDS"] == ROLE_WORDS


def test_the_guides_and_ides_words_are_served() -> None:
    """guide.js and main.js ask for these by key (`test_every_word_a_script_asks_for_is_served`
    holds each key they ask for); a bold mark ``**`` comes in pairs."""
    served = vocabulary()
    assert served["GUIDE_WORDS"] == GUIDE_WORDS
    assert served["IDE_WORDS"] == IDE_WORDS
    assert all(text.count("**") % 2 == 0 for text in GUIDE_WORDS.values())


def test_a_role_reaches_the_screen_as_its_name() -> None:
    """``el("td", {}, u.role)`` or ``${app.role}`` shows the code ("instructor"): a script
    shows ``ROLE_WORDS[u.role]`` (the code itself only after it, for a role this page does
    not know yet)."""
    named = re.compile(r"ROLE_WORDS\[([\w.?]+\.role)\](\s*\?\?\s*\1)?")
    found = []
    for path in _scripts():
        for number, line in enumerate(_code(path).splitlines(), 1):
            rest = named.sub("", line)
            shown = _SHOWN_ON.search(rest) or "${" in rest
            if shown and re.search(r"\.role\b(?!\s*(\?|[!=]==))", rest):
                found.append(f"{path.relative_to(SRC)}:{number}: {line.strip()}")
    assert not found, "a role's code shown (show ROLE_WORDS of it):\n" + "\n".join(found)


def test_every_client_names_the_robots_alike() -> None:
    """The header's switch (``TARGET_LABELS`` from /vocab.js), the server's ``hello`` and
    the desktop client name the lab robot and one's simulator with `melfa.vocab.targets`."""
    from melfa.desktop.api import TARGET_LABELS as DESKTOP_LABELS
    from melfa.web.targets import PRIVATE_LABEL, Targets

    assert DESKTOP_LABELS == TARGET_LABELS == vocabulary()["TARGET_LABELS"]
    assert TARGET_LABELS["mine"] == PRIVATE_LABEL
    lab_default = Targets.__init__.__kwdefaults__["lab_label"]
    assert lab_default == TARGET_LABELS["lab"]


class _PageText(HTMLParser):
    """A page's text and the words of its attributes, each with its line; what its script
    fills (``data-w="key"``) gathered apart."""

    SHOWN_ATTRIBUTES = ("title", "aria-label", "placeholder", "alt")

    def __init__(self) -> None:
        super().__init__()
        self.text: list[tuple[int, str]] = []
        self.keys: list[tuple[int, str]] = []
        self._skip = 0

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        line = self.getpos()[0]
        if tag in ("script", "style"):
            self._skip += 1
        for name, value in attrs:
            if name in self.SHOWN_ATTRIBUTES and value:
                self.text.append((line, value))
            if (name == "data-w" or name.startswith("data-w-")) and value:
                self.keys.append((line, value))

    def handle_endtag(self, tag: str) -> None:
        if tag in ("script", "style"):
            self._skip -= 1

    def handle_data(self, data: str) -> None:
        if not self._skip and data.strip():
            self.text.append((self.getpos()[0], data.strip()))


def _page(name: str) -> _PageText:
    parser = _PageText()
    parser.feed(_code(STATIC / name))
    return parser


def test_the_desk_page_writes_no_word() -> None:
    """desk.html's every word is `DESK_WORDS`'s, set by desk.js (``data-w``, ``data-w-
    placeholder`` …): only the brand and signs are written in the page."""
    own = {"melfa", "◢"}
    found = [
        f"web/static/desk.html:{line}: {text!r}"
        for line, text in _page("desk.html").text
        if text not in own and re.search(r"[A-Za-z]{2}", text) and not text[0].isdigit()
    ]
    assert not found, "words written in the page (put them in DESK_WORDS):\n" + "\n".join(found)


def test_every_word_a_page_asks_for_is_served() -> None:
    """``data-w="find"`` on the desk must be a key of `DESK_WORDS` (else the page shows
    "undefined")."""
    desk = vocabulary()["DESK_WORDS"]
    missing = [
        f"desk.html:{line}: {key}" for line, key in _page("desk.html").keys if key not in desk
    ]
    assert not missing, "asked of DESK_WORDS but not there:\n" + "\n".join(missing)
