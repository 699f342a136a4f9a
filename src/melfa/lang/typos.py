"""Typo suggestions: "Did you mean WHILE instead of WIHLE?".

The rule, chosen so that the thesis's examples come out right (WIHLE, KOSUB and KOSU get a
suggestion, KOKUB does not):

* distance is the optimal-string-alignment distance: insert, delete, substitute or swap two
  neighbouring letters, each costing 1 (so WIHLE is 1 from WHILE, not 2);
* a word of up to 5 letters may be 1 away from a keyword, a longer word 2 away;
* a word still being typed (3 letters or more, shorter than the keyword) also matches when it
  is within 1 of the keyword's start of the same length (KOSU ~ GOSU, so GOSUB).

Plain Levenshtein cannot separate KOSU from KOKUB (both 2 from GOSUB); the prefix rule can.
"""

from __future__ import annotations

from collections.abc import Iterable


def osa_distance(a: str, b: str, limit: int = 3) -> int:
    """Optimal-string-alignment distance, capped at `limit` (cheap early exit).

    >>> osa_distance("WIHLE", "WHILE"), osa_distance("KOKUB", "GOSUB")
    (1, 2)
    """
    if a == b:
        return 0
    if abs(len(a) - len(b)) >= limit:
        return limit
    prev2: list[int] = []
    prev = list(range(len(b) + 1))
    for i in range(1, len(a) + 1):
        cur = [i] + [0] * len(b)
        ai = a[i - 1]
        for j in range(1, len(b) + 1):
            cost = 0 if ai == b[j - 1] else 1
            v = min(prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost)
            if i > 1 and j > 1 and ai == b[j - 2] and a[i - 2] == b[j - 1]:
                v = min(v, prev2[j - 2] + 1)
            cur[j] = v
        if min(cur) >= limit:
            return limit
        prev2, prev = prev, cur
    return min(prev[len(b)], limit)


def _threshold(word: str) -> int:
    return 1 if len(word) <= 5 else 2


def suggest(word: str, candidates: Iterable[str]) -> str | None:
    """The closest candidate under the rule above, or None.

    >>> words = ["WHILE", "GOSUB", "GOTO", "HLT"]
    >>> [suggest(w, words) for w in ["WIHLE", "KOSUB", "KOSU", "KOKUB", "HALT"]]
    ['WHILE', 'GOSUB', 'GOSUB', None, 'HLT']
    """
    up = word.upper()
    limit = _threshold(up)
    best: tuple[int, str] | None = None
    for cand in candidates:
        if cand == up:
            continue
        d = osa_distance(up, cand, limit + 1)
        if d > limit and 3 <= len(up) < len(cand):
            d = osa_distance(up, cand[: len(up)], 2) + 1  # prefix match ranks after full ones
            if d > 2:
                continue
        elif d > limit:
            continue
        if best is None or (d, cand) < best:
            best = (d, cand)
    return None if best is None else best[1]
