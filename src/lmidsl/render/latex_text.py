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
}
_UNICODE_TEXT = {"–": "--", "—": "---", "‘": "`", "’": "'", "“": "``", "”": "''", "…": r"\dots{}",
                 "\u00a0": "~", "°": r"\ensuremath{^\circ}"}
_SUPERSCRIPTS = dict(zip("⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻ᵀⁱⁿ", "0123456789+-Tin"))
_SUBSCRIPTS = dict(zip("₀₁₂₃₄₅₆₇₈₉₊₋ᵢⱼₖ", "0123456789+-ijk"))
_COMBINING = {"\u0302": r"\hat", "\u0304": r"\bar", "\u0305": r"\bar", "\u0303": r"\tilde",
              "\u0307": r"\dot", "\u030c": r"\check"}
_COMBINING_TEXT = {"\u0301": r"\'", "\u0300": r"\`", "\u0308": r"\"", "\u0327": r"\c"}


def _greek_of(ch: str) -> str | None:
    try:
        name = unicodedata.name(ch)
    except ValueError:
        return None
    m = re.fullmatch(r"GREEK (SMALL|CAPITAL) LETTER (\w+)", name)
    if not m:
        return None
    word = m.group(2).lower()
    word = {"lamda": "lambda", "omicron": "o"}.get(word, word)
    if m.group(1) == "CAPITAL":
        word = word.capitalize()
        if word not in _GREEK:
            return word[0]
    return "\\" + word if word != "o" else "o"


def tex_text(text: str) -> str:
    r"""Plain text (with Unicode mathematics: γ², r̄, Âf, ≤, ⁻¹) as LaTeX text for pdflatex."""
    pieces: list[list] = []  # [kind, latex] with kind "m" (math) or "t" (text)

    def add(kind, s):
        pieces.append([kind, s])

    for ch in unicodedata.normalize("NFD", str(text)):
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
            add("m", greek) if greek else add("t", "?")
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
