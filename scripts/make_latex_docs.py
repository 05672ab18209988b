"""docs/latex/: the LaTeX document of each listed theorem (with its example solved), its PDF and a
PNG of page 1 — what `lmidsl latex THEOREM [--example NAME] -o docs/latex/THEOREM.tex --pdf` writes;
for the documents of the largest LMIs (:data:`LARGEST`), a PNG of every page at full size.

    python scripts/make_latex_docs.py [--out DIR]

Needs pdflatex (Debian: texlive-latex-base); the PNG needs pdftoppm (poppler-utils) and is
skipped, saying so, without it.  Exit code 0 when every document compiled, 1 otherwise.
"""
from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
from pathlib import Path

from lmidsl.cli.latex_cmd import compile_pdf
from lmidsl.pipeline import solve
from lmidsl.render.latex_document import theorem_latex

ROOT = Path(__file__).resolve().parents[1]
#: theorem → example solved in its document (None: the statement only)
DOCUMENTS = {
    "wang_l2linf.thm1": "paper-full-printed", "wang_l2linf.thm3": "paper-full",
    "wang_l2linf.cor1": "two-vertex", "li_delay_dropout.thm1": None,
    "li_delay_dropout.thm2": "paper", "zhang_quantized_loss.thm1": None,
    "zhang_quantized_loss.exact": None, "pan_impulsive.lemma1": None, "pan_impulsive.thm1": None,
    "interconnected_delay.thm1": None, "interconnected_delay.thm2": None,
}

#: the documents of the largest LMIs (9, 10 and 6 block rows, two LMIs each): every page as PNG
LARGEST = ("interconnected_delay.thm2", "zhang_quantized_loss.exact", "pan_impulsive.thm1")
#: resolution of the PNGs (dots per inch): page 1 of each document, every page of LARGEST
DPI, LARGE_DPI = 90, 110


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(ROOT / "docs" / "latex"))
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    png = shutil.which("pdftoppm")
    if png is None:
        print("make_latex_docs: pdftoppm not installed (apt-get install poppler-utils): no PNG",
              file=sys.stderr)
    failed = 0
    for theorem, example in DOCUMENTS.items():
        solution = solve(theorem, example=example) if example else None
        tex = out / f"{theorem}.tex"
        tex.write_text(theorem_latex(theorem, solution))
        try:
            pdf = compile_pdf(tex)
        except Exception as exc:  # noqa: BLE001  (report every document, then fail)
            print(f"{theorem}: {exc}", file=sys.stderr)
            failed += 1
            continue
        if png:
            for old in out.glob(f"{theorem}-*.png"):
                old.unlink()
            if theorem in LARGEST:
                subprocess.run([png, "-r", str(LARGE_DPI), "-png", str(pdf), str(out / theorem)], check=True)
                for page in out.glob(f"{theorem}-*.png"):      # pdftoppm pads page numbers: -01
                    page.rename(out / f"{theorem}-{int(page.stem.rsplit('-', 1)[1])}.png")
            else:
                subprocess.run([png, "-r", str(DPI), "-png", "-f", "1", "-l", "1", "-singlefile", str(pdf),
                                str(out / f"{theorem}-1")], check=True)
        print(f"{theorem}: {pdf.name}" + (f", {theorem}-1.png" if png else ""), flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
