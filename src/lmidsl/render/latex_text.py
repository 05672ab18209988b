"""Plain text and numbers for LaTeX: Unicode mathematics in descriptions (γ², r̄, Âf, ≤)
becomes pdflatex-safe LaTeX; floats and numeric matrices get a fixed number of digits."""
from __future__ import annotations

import re
import unicodedata

import numpy as np

_GREEK = {"alpha", "beta", "gamma", "delta", "epsilon", "varepsilon", "zeta", "eta", "theta",
          "vartheta", "iota", "kappa", "lambda", "mu", "nu", "xi", "pi", "rho", "sigma", "tau",
          "upsilon", "phi", "varphi", "chi", "psi", "omega", "Gamma", "Delta", "Theta", "Lambda",
          "Xi", "Pi", "Sigma", "Upsilon", "Phi", "Psi", "Omega"}

# -- text -------------------------------------------------------------------------------
_TEXT_ESCAPES = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#",
                 "_": r"\_", "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}",
                 "^": r"\textasciicircum{}"}
_TEXT_MATH = {"<": "<", ">": ">", "|": "|"}
_UNICODE_MATH = {
    "≤": r"\le", "≥": r"\ge", "≠": r"\ne", "≈": r"\approx", "×": r"\times", "·": r"\cdot",
    "∞": r"\infty", "∈": r"\in", "√": r"\surd", "∑": r"\sum", "∏": r"\prod", "→": r"\to",
    "⇔": r"\Leftrightarrow", "⇒": r"\Rightarrow", "±": r"\pm", "⋆": r"\star", "≺": r"\prec",
    "≻": r"\succ", "⪯": r"\preceq", "⪰": r"\succeq", "∀": r"\forall", "ℓ": r"\ell",
    "∂": r"\partial", "∇": r"\nabla", "−": "-", "⊗": r"\otimes", "∘": r"\circ",
    "←": r"\leftarrow", "↦": r"\mapsto", "⇐": r"\Leftarrow", "↔": r"\leftrightarrow", "∉": r"\notin",
    "⊂": r"\subset", "⊆": r"\subseteq", "∪": r"\cup", "∩": r"\cap", "∅": r"\emptyset", "∗": "*",
    "⊤": "T", "∼": r"\sim", "≡": r"\equiv", "≪": r"\ll", "≫": r"\gg", "∃": r"\exists", "′": "'",
    "ℝ": r"\mathbb{R}", "ℂ": r"\mathbb{C}", "ℕ": r"\mathbb{N}", "‖": r"\|", "⟨": r"\langle", "⟩": r"\rangle",
}
_UNICODE_TEXT = {"–": "--", "—": "---", "‘": "`", "’": "'", "“": "``", "”": "''", "…": r"\dots{}",
                 "\u00a0": "~", "°": r"\ensuremath{^\circ}", "§": r"\S{}", "¶": r"\P{}",
                 "•": r"\textbullet{}", "×": r"\ensuremath{\times}"}
_SUPERSCRIPTS = dict(zip("⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻ᵀⁱⁿ⁽⁾", "0123456789+-Tin()"))
_SUBSCRIPTS = dict(zip("₀₁₂₃₄₅₆₇₈₉₊₋ᵢⱼₖ₍₎", "0123456789+-ijk()"))
_COMBINING = {"\u0302": r"\hat", "\u0304": r"\bar", "\u0305": r"\bar", "\u0303": r"\tilde",
              "\u0307": r"\dot", "\u030c": r"\check"}
_COMBINING_TEXT = {"\u0301": r"\'", "\u0300": r"\`", "\u0308": r"\"", "\u0327": r"\c"}


def _greek_of(ch: str) -> str | None:
    try:
        name = unicodedata.name(ch)
    except ValueError:
        return None
    m = re.fullmatch(r"GREEK (SMALL|CAPITAL) LETTER (\w+)|GREEK (\w+) SYMBOL", name)
    if not m:
        return None
    if m.group(3):      # ϑ, ϕ, ϵ, ϱ, ϖ, ϰ: the symbol variants
        return {"THETA": r"\vartheta", "PHI": r"\phi", "RHO": r"\varrho", "PI": r"\varpi",
                "KAPPA": r"\varkappa", "LUNATE EPSILON": r"\epsilon"}.get(m.group(3))
    word = m.group(2).lower()
    word = {"lamda": "lambda", "omicron": "o"}.get(word, word)
    if m.group(1) == "CAPITAL":
        word = word.capitalize()
        if word not in _GREEK:
            return word[0]
    return "\\" + word if word != "o" else "o"


def _char_text(text: str) -> str:
    """Text with Unicode mathematics, character by character: a maths character becomes maths,
    the rest is escaped text (the part of :func:`tex_text` outside code-like spans)."""
    pieces: list[list] = []  # [kind, latex] with kind "m" (math) or "t" (text)

    def add(kind, s):
        pieces.append([kind, s])

    for ch in _nfd(text):
        if ch in _COMBINING:
            if pieces and len(pieces[-1][1]) and (pieces[-1][0] == "m" or pieces[-1][1].isalpha()):
                pieces[-1] = ["m", f"{_COMBINING[ch]}{{{pieces[-1][1]}}}"]
            continue
        if ch in _COMBINING_TEXT:
            if pieces and pieces[-1][0] == "t" and pieces[-1][1].isalpha():
                pieces[-1][1] = f"{_COMBINING_TEXT[ch]}{{{pieces[-1][1]}}}"
            continue
        if ch in _TEXT_ESCAPES:
            add("t", _TEXT_ESCAPES[ch])
        elif ch in _TEXT_MATH:
            add("m", _TEXT_MATH[ch])
        elif ch in _SUPERSCRIPTS or ch in _SUBSCRIPTS:
            sup = ch in _SUPERSCRIPTS
            mark, char = ("^", _SUPERSCRIPTS[ch]) if sup else ("_", _SUBSCRIPTS[ch])
            if pieces and pieces[-1][0] == "m" and pieces[-1][1].startswith(mark + "{"):
                pieces[-1][1] = pieces[-1][1][:-1] + char + "}"
            else:
                add("m", f"{mark}{{{char}}}")
        elif ch in _UNICODE_MATH:
            add("m", _UNICODE_MATH[ch])
        elif ch in _UNICODE_TEXT:
            add("t", _UNICODE_TEXT[ch])
        elif ord(ch) < 128:
            add("t", ch)
        else:
            greek = _greek_of(ch)
            add("m", greek) if greek else add("t", _unknown(ch))
    out, math = [], []
    for kind, s in pieces:
        if kind == "m":
            if math and s[0].isalpha() and math[-1][-1:].isalpha() and math[-1].startswith("\\"):
                math.append(" ")
            math.append(s)
            continue
        if math:
            out.append("$" + "".join(math) + "$")
            math = []
        out.append(s)
    if math:
        out.append("$" + "".join(math) + "$")
    return "".join(out)


def _unknown(ch: str) -> str:
    """A character with no LaTeX mapping: its ASCII decomposition, else its code point (never a
    silent '?')."""
    plain = unicodedata.normalize("NFKD", ch).encode("ascii", "ignore").decode()
    return "".join(_TEXT_ESCAPES.get(c, c) for c in plain) or f"[U+{ord(ch):04X}]"


# -- code-like spans: identifiers with _ ^ or digits, Greek, relations → one $...$ ----------
#: ASCII names of Greek letters written in code-like text (tau_ij, alpha); not the ones that are
#: also prose words here ("delta reading", "eta", "pi")
_ASCII_GREEK = _GREEK - {"delta", "Delta", "eta", "pi", "Pi"}
#: operator words set upright when they open a code-like span (diag(...), Pr{...}, Re s)
_OPERATORS = {"diag": r"\mathrm{diag}", "tr": r"\operatorname{tr}", "Pr": r"\Pr", "Re": r"\operatorname{Re}",
              "Im": r"\operatorname{Im}", "He": r"\operatorname{He}", "inf": r"\inf", "sup": r"\sup",
              "det": r"\det", "rank": r"\operatorname{rank}", "min": r"\min", "max": r"\max"}
_LETTER = r"(?:[A-Za-z\u0370-\u03FF\u2113][\u0300-\u036F]*)"
_SUPS = "".join(_SUPERSCRIPTS) + "".join(_SUBSCRIPTS) + "⁽⁾"
#: dotted or slashed names (theorem ids, modules, paths): prose, never maths
_ABBREVIATION = re.compile(r"(?:s\.t|e\.g|i\.e|cf|resp|etc|vs)\.")
_CODE_NAME = re.compile(r"[A-Za-z_][\w-]+(?:[./][\w-]+)+")
_NUMBER = r"[0-9]+(?:\.[0-9]+)?(?:e-?[0-9]+)?"
_WORD = re.compile(r"(?:[0-9]+(?:\.[0-9]+)?(?:e-?[0-9]+)?(?![A-Za-z0-9]))|"
                   r"(?:_\{[^{}]*\}|[A-Za-z0-9\u0370-\u03FF\u2113\u0300-\u036F_" + _SUPS + r"∞]|"
                   r"\^\([^()\s]*\)|\^\{[^{}]*\}|\^-?\w+)+(?:'[A-Za-z]+)*")
_RELATION = {"=", "<", ">", "≤", "≥", "≠", "≈", "≺", "≻", "⪯", "⪰", "∈", "→", "+", "-", "−", "*", "/",
             "·", "×", "⊗", "±"}
_SINGLE_NOT_MATH = {"a", "A"}


def _is_math_word(word: str) -> bool:
    """Is this word code or mathematics (x_j, tau_ij, Z^-1, P1, M11, Âf, γ, l2) rather than prose?"""
    base = unicodedata.normalize("NFD", word)
    if "'" in base or base[:1].isdigit():
        return False
    if "_" in base or "^" in base or any(c in _SUPS or c == "∞" for c in base):
        return True
    if any("\u0300" <= c <= "\u036F" for c in base):
        return True
    letters = [c for c in base if c.isalpha()]
    if all(_greek_of(c) for c in letters):
        return True                                         # γ, ρ, Σρ
    if base in _ASCII_GREEK or re.fullmatch(r"[\u0370-\u03FF][A-Z][0-9]*", base):
        return True                                         # tau, αP
    if re.fullmatch(r"[A-Za-z]", base):
        return base not in _SINGLE_NOT_MATH
    return bool(re.fullmatch(r"[A-Za-z\u0370-\u03FF]{1,2}[0-9]+[a-z]?[A-Z]?", base))   # P1, H2, M11, P1i, B2K


def _nfd(text: str) -> str:
    """NFD, but with the negated relations (≠, ∉) kept whole."""
    return unicodedata.normalize("NFD", str(text)).replace("=\u0338", "≠").replace("∈\u0338", "∉")


def _math_chars(text: str) -> str:
    """Characters as LaTeX maths (no ``$``): Greek and symbols as commands, accents, scripts."""
    out: list[str] = []
    for ch in _nfd(text):
        if ch in _COMBINING and out:
            out[-1] = f"{_COMBINING[ch]}{{{out[-1].strip()}}}"
        elif ch in _SUPERSCRIPTS or ch in _SUBSCRIPTS:
            mark, char = ("^", _SUPERSCRIPTS[ch]) if ch in _SUPERSCRIPTS else ("_", _SUBSCRIPTS[ch])
            if out and out[-1].startswith(mark + "{"):
                out[-1] = out[-1][:-1] + char + "}"
            else:
                if out:
                    out[-1] = out[-1].rstrip()               # \gamma^{2}, not \gamma ^{2}
                out.append(f"{mark}{{{char}}}")
        elif ch in _UNICODE_MATH:
            out.append(_UNICODE_MATH[ch] + (" " if _UNICODE_MATH[ch][-1:].isalpha() else ""))
        elif ch in "{}":
            out.append("\\" + ch)
        elif ord(ch) < 128:
            out.append(ch)
        else:
            greek = _greek_of(ch)
            out.append(greek + " " if greek else _unknown(ch))
    return "".join(out).strip()


#: one factor of a product written without spaces: a capital (accented), an index of small
#: letters or digits, scripts (Âf, Z⁻¹, G22⁻¹, Mᵀ, S⁻ᵀ)
_FACTOR = re.compile("[A-Z][\u0300-\u036F]*(?:[a-z]{1,2}(?![a-z])|[0-9]+)?[" + _SUPS + "]*")

_SUB_WORDS = {"min": r"\min", "max": r"\max", "inf": r"\inf", "sup": r"\sup"}


def _math_word(word: str) -> str:
    """A code-like word as LaTeX maths: tau_ij → \\tau_{ij}, Z^-1 → Z^{-1}, P1i → P_{1i},
    A_1_1 → A_{1,1}, A_iᵀP → A_i^{T}P, Âf → \\hat{A}_{f}."""
    if all(c in _SUPS for c in word):                        # ⁻¹ alone
        return _math_chars(word)
    factors = _FACTOR.findall(word)
    if len(factors) > 1 and "".join(factors) == word and re.search(
            "[a-z\u0300-\u036F" + _SUPS + "]", word):            # R⁻¹ÂfZ⁻¹S⁻ᵀ: a product
        return " ".join(_math_word(f) for f in factors)
    tail = ""
    while word[-1] in _SUPS:                                 # P̌3⁻¹, T_cᵀ: trailing scripts
        tail = word[-1] + tail
        word = word[:-1]
    if tail:
        return _math_word(word) + _math_chars(tail)
    m = re.fullmatch(r"((?:[A-Za-z][\u0300-\u036F]*){1,2}|[\u0370-\u03FF][\u0300-\u036F]*)"
                     r"([0-9]+[a-z]?|∞)([A-Z]?)", word)
    if m:                                                   # P1i, M11, H∞, l2, P̌3, B2K
        base = r"\ell" if m.group(1) == "l" else _math_chars(m.group(1))
        sub = r"\infty" if m.group(2) == "∞" else m.group(2)
        return f"{base}_{{{sub}}}{m.group(3)}"
    m = re.fullmatch(r"([A-Z][\u0300-\u036F]*)([a-z]{1,3})", word)
    if m:                                                   # Âf, B̂fi, Af: matrix, index
        return f"{_math_chars(m.group(1))}_{{{m.group(2)}}}"
    out, i = [], 0
    head = re.match(r"[A-Za-z]+(?=_|\^|$)", word)
    if head and (head.group() in _ASCII_GREEK or head.group() in _SUB_WORDS):
        out.append("\\" + head.group() + " ")                 # tau_ij, inf_ω
        i = head.end()
    last_sub = False
    while i < len(word):
        ch = word[i]
        if ch == "_":
            m = re.compile(r"\{([^{}]*)\}|([A-Za-z0-9\u0370-\u03FF]+)").match(word, i + 1)
            if not m:
                i += 1
                continue
            part = m.group(1) if m.group(1) is not None else m.group(2)
            part = _SUB_WORDS.get(part, "\\" + part + " " if part in _ASCII_GREEK else _math_chars(part))
            if last_sub:                                    # A_1_1 → A_{1,1}
                out[-1] = out[-1][:-1] + "," + part.strip() + "}"
            else:
                if out:
                    out[-1] = out[-1].rstrip()
                out.append("_{" + part.strip() + "}")
            last_sub = True
            i = m.end()
            continue
        last_sub = False
        if ch == "^":
            m = re.compile(r"\(([^()]*)\)|\{([^{}]*)\}|(-?\w+)").match(word, i + 1)
            if m:
                body = next(g for g in m.groups() if g is not None)
                if out:
                    out[-1] = out[-1].rstrip()
                out.append("^{" + _math_chars(body) + "}")
                i = m.end()
                continue
        run = re.compile(r"[^_^{}]+").match(word, i)
        if run is None:                                     # a stray brace
            i += 1
            continue
        out.append(_math_chars(run.group()))
        i = run.end()
    return "".join(out).strip()


def _tokens(text: str):
    """(kind, text): 'w' word, 's' space, 'o' relation/operator, 'p' bracket, 'x' other."""
    i = 0
    while i < len(text):
        m = _ABBREVIATION.match(text, i)
        if m and (i == 0 or not text[i - 1].isalnum()):
            yield "x", m.group()
            i = m.end()
            continue
        m = _CODE_NAME.match(text, i)
        if m and (i == 0 or not text[i - 1].isalnum()):
            yield "x", m.group()
            i = m.end()
            continue
        m = _WORD.match(text, i)
        if m and m.end() > i:
            yield "w", m.group()
            i = m.end()
            continue
        ch = text[i]
        kind = "s" if ch == " " else "o" if ch in _RELATION else "p" if ch in "()[]{}" else "x"
        yield kind, ch
        i += 1


def _math_spans(text: str):
    """Split ``text`` into ('m', code-like span) and ('t', prose) pieces."""
    toks = list(_tokens(text))
    out, i = [], 0

    def text_after(k):
        return "".join(t for _, t in toks[k + 1:k + 4])

    while i < len(toks):
        kind, t = toks[i]
        nxt = next((u for u in toks[i + 1:] if u[0] != "s"), ("x", ""))
        opens = kind == "w" and (_is_math_word(t) or (t in _OPERATORS and i + 1 < len(toks)
                                                    and toks[i + 1][1] in "({")
                                 or (t in _SINGLE_NOT_MATH and (nxt[0] == "o" or nxt[0] == "w"
                                                                and _is_math_word(nxt[1]))))
        if (not opens and kind == "w" and re.fullmatch(r"[A-Z][a-z]{1,2}", t)
                and "".join(u for _, u in toks[i + 1:i + 3]).strip().startswith("=")):
            opens = True                                    # Af = ...: a matrix name (A_f)
        if opens and i > 0 and toks[i - 1][1] in "'’":     # the paper's: prose
            opens = False
        if opens and re.fullmatch(r"[A-Z]", t) and re.match(r"\. [A-Z]", text_after(i)):
            opens = False                                   # an initial: Int. J. Robust
        if not opens:
            out.append(("t", t))
            i += 1
            continue
        j, depth, last = i + 1, 0, i          # last: index of the last token inside the span
        while j < len(toks):
            k2, t2 = toks[j]
            if k2 == "w":
                if not (_is_math_word(t2) or re.fullmatch(_NUMBER, t2)
                        or re.fullmatch(r"[a-z][A-Z][0-9]*|[Aa]", t2)     # hR, hP3, A after '='

                        or (t2 in _OPERATORS and j + 1 < len(toks) and toks[j + 1][1] in "({ ")):
                    break
                if depth == 0:
                    last = j
            elif k2 == "p":
                if t2 in "([{":
                    depth += 1
                elif depth == 0:
                    break
                else:
                    depth -= 1
                    if depth == 0:
                        last = j
            elif k2 == "x" and not (depth and t2 in ",;|") and not (
                    t2 == "," and j + 1 < len(toks) and toks[j + 1][0] == "w"
                    and _is_math_word(toks[j + 1][1])):            # ϑ1,k
                break
            j += 1
        # a bracket opened inside the span and not closed there ends it before the bracket
        span = toks[i:last + 1]
        out.append(("m", span))
        i = last + 1
    return out


def _span_tex(span) -> str:
    parts = []
    for kind, t in span:
        if kind == "w":
            if t in _OPERATORS:
                parts.append(_OPERATORS[t] + (" " if not _OPERATORS[t].endswith("}") else ""))
            elif re.fullmatch(r"[0-9.]+e-?[0-9]+", t):   # 1e-4
                mant, exp = t.split("e")
                parts.append(rf"{mant} \cdot 10^{{{int(exp)}}}")
            elif re.fullmatch(r"[0-9.]+", t):
                parts.append(t)
            else:
                parts.append(_math_word(t))
        elif kind == "s":
            parts.append(" ")
        else:
            parts.append(_math_chars(t))
    return re.sub(r"\s+", " ", "".join(parts)).strip()


#: a path inside the repository (docs/..., theorems/...), with what follows it up to the bracket
_REPO_PATH = r"(?:docs|src|theorems|tests|scripts|benchmarks)/[\w./-]+(?:,[^()]*)?"


#: a path that is part of a sentence, and the words a printed document says instead
_BARE_PATH = r"\b(docs/reproductions|docs|src|theorems|tests|scripts|benchmarks)/[\w./-]*\w"
_PATH_WORDS = {"docs/reproductions": "lmidsl's reproduction report", "theorems": "lmidsl's theorem files",
               "src": "lmidsl's source", "tests": "lmidsl's tests", "scripts": "lmidsl's scripts",
               "benchmarks": "lmidsl's benchmarks"}


def without_repository_paths(text: str) -> str:
    """``text`` without references to files of the repository, which a reader of the printed
    document cannot open: "(… ; docs/x.md)" keeps "(…)", "(docs/x.md, section 4)" goes, and a
    path that is part of a sentence becomes words ("lmidsl's reproduction report")."""
    text = re.sub(r";\s*" + _REPO_PATH + r"(?=\))", "", text)
    text = re.sub(r"\s*\(" + _REPO_PATH + r"\)", "", text)
    return re.sub(_BARE_PATH, lambda m: _PATH_WORDS.get(m.group(1), "lmidsl's documentation"), text)


def _plain_notation(text: str) -> str:
    """Code habits to mathematics: ``A_<i>`` → ``A_i``; ``k_i x k_i``, ``3 x 3`` → ``×``."""
    text = re.sub(r"_<(\w+)>", r"_\1", text)
    return re.sub(r"(?<![\w])([A-Za-z0-9]{1,3}(?:_\w{1,3})?) x ([A-Za-z0-9]{1,3}(?:_\w{1,3})?)(?![\w])",
                  r"\1 × \2", text)


def tex_text(text: str) -> str:
    r"""Plain text (with Unicode mathematics: γ², r̄, Âf, ≤, ⁻¹) as LaTeX text for pdflatex.

    Code-like spans (``x_j(t - tau_ij)``, ``I - X Z^-1``, ``P1 > 0``) and Unicode mathematics
    are set as maths in ``$...$``; the rest is escaped text.  References to the repository's
    files are left out (:func:`without_repository_paths`)."""
    out = []
    text = _plain_notation(without_repository_paths(_nfd(text)))
    text = text.replace("->", "→").replace("<=", "≤").replace(">=", "≥")
    for kind, piece in _math_spans(text):
        out.append("$" + _span_tex(piece) + "$" if kind == "m" else _char_text(piece))
    joined = "".join(out)
    return joined.replace("$$", " ")       # two adjacent maths pieces are one


# -- numbers -----------------------------------------------------------------------------
def latex_number(x: float, digits: int = 4) -> str:
    """A float with ``digits`` significant digits, exponents as ``\\times 10^{k}``."""
    x = float(x)
    if not np.isfinite(x):
        return r"\infty" if x > 0 else (r"-\infty" if x < 0 else r"\mathrm{NaN}")
    if x == 0:
        return "0"
    s = f"{x:.{digits}g}"
    if "e" in s:
        mant, exp = s.split("e")
        return rf"{mant} \times 10^{{{int(exp)}}}"
    return s


def latex_matrix(M, digits: int = 4, env: str = "bmatrix") -> str:
    """A numeric matrix as a bmatrix (a 1×1 matrix as its number)."""
    M = np.atleast_2d(np.asarray(M, dtype=float))
    if M.shape == (1, 1):
        return latex_number(M[0, 0], digits)
    rows = " \\\\ ".join(" & ".join(latex_number(v, digits) for v in row) for row in M)
    return f"\\begin{{{env}}} {rows} \\end{{{env}}}"
