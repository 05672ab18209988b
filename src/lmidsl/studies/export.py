"""Export the compiled SDP of a bound theorem: SDPA sparse (.dat-s), CBF, and a JSON map.

The SDP is the one ``lmidsl solve`` hands to a solver: every LMI at every polytope vertex and
uncertainty scenario, strict ones as ``N ⪯ −εI`` with the strictness margin ε, compiled by the
PICOS backend.  The SDPA file is written by PICOS' own writer (``Problem.write_to_file``, which
goes through PICOS' CVXOPT form).  PICOS 2.6's CBF writer fails on these problems (a KeyError on
the scalar objective variable), so the CBF file is written here from the same numbers as the
SDPA file (:func:`read_sdpa` then :func:`write_cbf`): both files state one problem.

Both files state, in SDPA's convention,

    minimise cᵀx  subject to  F(x) = Σ_k x_k F_k − F_0 ⪰ 0   (blocks; negative size = diagonal)

where x is the concatenation of PICOS' vectorisations of the theorem's decision variables
(column-major for full matrices, PICOS' svec for symmetric ones).  The JSON map says which
entries of x are which variable and which block is which LMI (label, vertex, scenario), so a
solution read from any solver can be mapped back (:func:`variables_from_x`).
"""
from __future__ import annotations

import json
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError, LmidslError
from ..numeric.instance import Instance, random_point
from ..numeric.scaling import apply_scaling
from ..solver.backends import get_backend
from .defaults import FORMATS, OPTIMUM_RTOL



@dataclass
class SDPAProblem:
    """minimise cᵀx s.t. Σ_k x_k F_k − F_0 ⪰ 0; ``F[k][b]`` is a dense block (k = 0 is F_0)."""

    c: np.ndarray
    blocks: list[int]                       # SDPA block sizes (negative: diagonal block)
    F: list[list[np.ndarray]] = field(default_factory=list)

    @property
    def nvars(self) -> int:
        return len(self.c)


def read_sdpa(text: str) -> SDPAProblem:
    """A small reader of sparse SDPA (.dat-s): comments, m, nblocks, sizes, c, then entries."""
    lines = [ln for ln in text.splitlines() if ln.strip() and ln.strip()[0] not in '"*']
    clean = lambda s: s.replace("{", " ").replace("}", " ").replace("(", " ").replace(")", " ") \
        .replace(",", " ").split("=")[0]
    m = int(clean(lines[0]).split()[0])
    nblocks = int(clean(lines[1]).split()[0])
    sizes = [int(v) for v in clean(lines[2]).split()[:nblocks]]
    c = np.array([float(v) for v in clean(lines[3]).split()[:m]])
    F = [[np.zeros((abs(s), abs(s))) for s in sizes] for _ in range(m + 1)]
    for line in lines[4:]:
        k, b, i, j, v = line.split()
        k, b, i, j, v = int(k), int(b) - 1, int(i) - 1, int(j) - 1, float(v)
        F[k][b][i, j] = v
        F[k][b][j, i] = v
    return SDPAProblem(c, sizes, F)


def write_cbf(problem: SDPAProblem) -> str:
    """The same problem in CBF: ``PSDCON`` Σ_k x_k F_k − F_0 ⪰ 0 (HCOORD/DCOORD, lower triangles)."""
    out = ["# written by lmidsl from PICOS' SDPA form: min c'x s.t. sum_k x_k F_k - F_0 >= 0",
           "VER", "3", "", "OBJSENSE", "MIN", "", "VAR", f"{problem.nvars} 1", f"F {problem.nvars}", ""]
    sdp = [b for b, s in enumerate(problem.blocks) if s > 0]
    lin = [b for b, s in enumerate(problem.blocks) if s < 0]
    if lin:
        nlin = sum(-problem.blocks[b] for b in lin)
        out += ["CON", f"{nlin} 1", f"L+ {nlin}", ""]
    if sdp:
        out += ["PSDCON", str(len(sdp))] + [str(problem.blocks[b]) for b in sdp] + [""]
    obj = [(k, v) for k, v in enumerate(problem.c) if v != 0]
    out += ["OBJACOORD", str(len(obj))] + [f"{k} {float(v)!r}" for k, v in obj] + [""]
    if lin:
        acoord, bcoord, row = [], [], 0
        for b in lin:
            for i in range(-problem.blocks[b]):
                for k in range(1, problem.nvars + 1):
                    if problem.F[k][b][i, i] != 0:
                        acoord.append(f"{row} {k - 1} {float(problem.F[k][b][i, i])!r}")
                if problem.F[0][b][i, i] != 0:
                    bcoord.append(f"{row} {float(-problem.F[0][b][i, i])!r}")
                row += 1
        out += ["ACOORD", str(len(acoord))] + acoord + [""]
        out += ["BCOORD", str(len(bcoord))] + bcoord + [""]
    if sdp:
        hcoord, dcoord = [], []
        for index, b in enumerate(sdp):
            for k in range(problem.nvars + 1):
                M = problem.F[k][b]
                for i, j in zip(*np.nonzero(np.tril(M))):
                    if k == 0:
                        dcoord.append(f"{index} {i} {j} {float(-M[i, j])!r}")
                    else:
                        hcoord.append(f"{index} {k - 1} {i} {j} {float(M[i, j])!r}")
        out += ["HCOORD", str(len(hcoord))] + hcoord + [""]
        out += ["DCOORD", str(len(dcoord))] + dcoord + [""]
    return "\n".join(out)


def read_cbf(text: str) -> SDPAProblem:
    """Read back what :func:`write_cbf` writes (VAR F, CON L+, PSDCON, OBJ/A/B/H/DCOORD)."""
    tokens = [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    pos, sections = 0, {}
    while pos < len(tokens):
        key = tokens[pos]
        pos += 1
        if key in ("VER", "OBJSENSE"):
            sections[key] = tokens[pos]
            pos += 1
        elif key in ("VAR", "CON"):
            total, ncones = (int(v) for v in tokens[pos].split())
            sections[key] = (total, tokens[pos + 1: pos + 1 + ncones])
            pos += 1 + ncones
        elif key == "PSDCON":
            count = int(tokens[pos])
            sections[key] = [int(v) for v in tokens[pos + 1: pos + 1 + count]]
            pos += 1 + count
        else:
            count = int(tokens[pos])
            sections[key] = [tokens[pos + 1 + i].split() for i in range(count)]
            pos += 1 + count
    if sections.get("OBJSENSE") != "MIN":
        raise InputError("CBF: only OBJSENSE MIN is read")
    nvars = sections["VAR"][0]
    nlin = sections["CON"][0] if "CON" in sections else 0
    psd = sections.get("PSDCON", [])
    blocks = ([-nlin] if nlin else []) + psd
    F = [[np.zeros((abs(s), abs(s))) for s in blocks] for _ in range(nvars + 1)]
    c = np.zeros(nvars)
    for k, v in sections.get("OBJACOORD", []):
        c[int(k)] = float(v)
    for r, k, v in sections.get("ACOORD", []):
        F[int(k) + 1][0][int(r), int(r)] = float(v)
    for r, v in sections.get("BCOORD", []):
        F[0][0][int(r), int(r)] = -float(v)
    shift = 1 if nlin else 0
    for b, k, i, j, v in sections.get("HCOORD", []):
        M = F[int(k) + 1][int(b) + shift]
        M[int(i), int(j)] = M[int(j), int(i)] = float(v)
    for b, i, j, v in sections.get("DCOORD", []):
        M = F[0][int(b) + shift]
        M[int(i), int(j)] = M[int(j), int(i)] = -float(v)
    return SDPAProblem(c, blocks, F)


def solve_sdpa_cvxpy(problem: SDPAProblem, solver: str | None = None,
                     accept_inaccurate: bool = False) -> tuple[float, np.ndarray]:
    """Solve the standard-form SDP directly with cvxpy (a route independent of the theorem's
    compiler and of PICOS): the optimal cᵀx and x.  ``solver`` None: Clarabel, then CVXOPT;
    ``accept_inaccurate``: a point to reduced accuracy (optimal_inaccurate) is an answer too."""
    import cvxpy as cp
    x = cp.Variable(problem.nvars)
    constraints = []
    for b, size in enumerate(problem.blocks):
        expr = -problem.F[0][b] + sum(x[k - 1] * problem.F[k][b] for k in range(1, problem.nvars + 1)
                                      if np.any(problem.F[k][b]))
        if size < 0:
            constraints.append(cp.diag(expr) >= 0)
        else:
            constraints.append((expr + expr.T) / 2 >> 0)
    prob = cp.Problem(cp.Minimize(problem.c @ x), constraints)
    tried = []
    for name in ([solver] if solver else ["CLARABEL", "CVXOPT"]):
        try:
            with warnings.catch_warnings():      # "Solution may be inaccurate": the status says so
                warnings.simplefilter("ignore", UserWarning)
                prob.solve(solver=name)
        except cp.error.SolverError:
            tried.append(f"{name}: solver error")
            continue
        if prob.status == "optimal" or (accept_inaccurate and prob.status == "optimal_inaccurate"):
            return float(prob.value), np.asarray(x.value)
        tried.append(f"{name}: {prob.status}")
    raise LmidslError(f"the exported SDP read back: {'; '.join(tried)}")


def _picos_model(instance: Instance, margin: float | None):
    return get_backend("picos")(instance, margin=margin)


def export_map(model) -> dict:
    """Which entries of x are which decision variable, which block is which LMI."""
    import picos
    problem = model.problem
    variables, offset = [], 0
    by_picos = {id(v): key for key, v in model._variables.items()}
    for var in problem.variables.values():
        key = by_picos.get(id(var))
        name = var.name if key is None else (key[0] if key[1] is None else f"{key[0]}[vertex {key[1] + 1}]")
        vec = "svec (PICOS: off-diagonal entries scaled by sqrt 2)" \
            if isinstance(var, picos.SymmetricVariable) else "column-major"
        variables.append({"name": name, "picos_name": var.name, "offset": offset, "length": var.dim,
                          "shape": list(var.shape), "vectorization": vec})
        offset += var.dim
    lmi_keys = [key for key, _ in model.constraints]
    blocks, linear = [], []
    for key, con in zip(lmi_keys, problem.constraints.values()):
        label, vertex, point = key
        entry = {"lmi": label, "vertex": None if vertex is None else vertex + 1, "scenario": point,
                 "size": int(con.size[0]) if hasattr(con, "size") else None}
        if isinstance(con, picos.constraints.LMIConstraint):
            blocks.append(entry)
        else:
            linear.append(entry)
    # variables with a lower bound (nonneg scalars) are rows of the diagonal block too
    bounded = [entry["name"] for entry, var in zip(variables, problem.variables.values())
               if getattr(var, "_lower", None) is not None]
    out_blocks = []
    if linear or bounded:
        out_blocks.append({"block": 1, "kind": "diagonal (linear inequalities)", "lmis": linear,
                           "bounds": [f"{name} >= 0" for name in bounded]})
    for b in blocks:
        out_blocks.append({"block": len(out_blocks) + 1, "kind": "semidefinite", **b})
    thm = model.instance.theorem
    return {"theorem": thm.id, "example": model.instance.example,
            "convention": "minimise c'x subject to sum_k x_k F_k - F_0 >= 0 (SDPA); "
                          "strict LMIs N < 0 as N <= -margin*I, X > 0 as X >= margin*I",
            "margin": model.margin, "objective": str(thm.objective), "nvars": offset,
            "variables": variables, "blocks": out_blocks, "params": dict(model.instance.params)}


def _unsvec(part: np.ndarray, n: int) -> np.ndarray:
    """PICOS' svec undone: the upper triangle column by column, off-diagonal entries × √2."""
    M, pos = np.zeros((n, n)), 0
    for j in range(n):
        for i in range(j + 1):
            M[i, j] = M[j, i] = part[pos] if i == j else part[pos] / np.sqrt(2.0)
            pos += 1
    return M


def variables_from_x(mapping: dict, x: np.ndarray) -> dict:
    """The theorem's decision variables from a solution x of the exported SDP."""
    out = {}
    for v in mapping["variables"]:
        part = np.asarray(x[v["offset"]: v["offset"] + v["length"]], dtype=float)
        shape = tuple(v["shape"])
        if v["vectorization"].startswith("svec"):
            out[v["name"]] = _unsvec(part, shape[0])
        else:
            out[v["name"]] = part.reshape(shape, order="F") if shape != (1, 1) else float(part[0])
    return out


def _svec(M: np.ndarray) -> np.ndarray:
    """PICOS' svec (the inverse of :func:`_unsvec`)."""
    n = M.shape[0]
    return np.array([M[i, j] if i == j else M[i, j] * np.sqrt(2.0) for j in range(n) for i in range(j + 1)])


def x_from_variables(mapping: dict, values: dict) -> np.ndarray:
    """The exported SDP's x for the theorem's decision variables ``values`` (the layout of
    ``CompiledModel.values``: a per-vertex variable as a list): the inverse of
    :func:`variables_from_x`."""
    x = np.zeros(mapping["nvars"])
    for v in mapping["variables"]:
        name, _, vertex = v["name"].partition("[vertex ")
        value = values[name]
        if vertex:
            value = value[int(vertex.rstrip("]")) - 1]
        value = np.atleast_2d(np.asarray(value, dtype=float))
        part = _svec(value) if v["vectorization"].startswith("svec") else value.reshape(-1, order="F")
        x[v["offset"]: v["offset"] + v["length"]] = part
    return x


def blocks_at(problem: SDPAProblem, x: np.ndarray) -> list[np.ndarray]:
    """F(x) = Σ_k x_k F_k − F_0, block by block."""
    return [sum((x[k - 1] * problem.F[k][b] for k in range(1, problem.nvars + 1)), -problem.F[0][b])
            for b in range(len(problem.blocks))]


#: the encoding identity: at one point, cᵀx against the objective and each block's eigenvalues
#: against its LMI's (−N − εI), relative to the size of the numbers (rounding only)
IDENTITY_RTOL = 1e-9


def check_round_trip(instance: Instance, path: str | Path, mapping: dict, backend: str = "direct",
                     solver: str | None = None, **options) -> dict:
    """Read the file back and say whether it carries lmidsl's SDP: (1) the identity -- at three
    random points (numpy seed 0), cᵀx equals the objective and the blocks of F(x) have the
    eigenvalues of the LMIs' −N − εI (ε the file's margin); (2) the file, solved by cvxpy, gives
    lmidsl's optimum of the same SDP (``backend``, the file's margin and scaling, as written:
    no conditioning, no margin reduction) within :data:`OPTIMUM_RTOL`.
    ``holds``, and ``reason`` when not: what the file cannot carry, or why it gives no point."""
    out = {"holds": False, "reason": ""}
    try:
        problem = read_back(path)
    except (OSError, ValueError, IndexError, KeyError) as exc:
        out["reason"] = f"the file cannot be read back ({type(exc).__name__}: {exc})"
        return out
    scaled = apply_scaling(instance, "auto").scaled
    model = get_backend(backend)(scaled, margin=mapping["margin"])
    rng = np.random.default_rng(0)
    identity = 0.0
    for _ in range(3):
        point = random_point(scaled, rng)
        values = {name: point[name] for name in scaled.theorem.var_decl if name in point}
        model.assign(values)
        error = _identity_error(problem, x_from_variables(mapping, values), model)
        identity = None if error is None or identity is None else max(identity, error)
    out["identity_error"] = identity
    if identity is None or identity > IDENTITY_RTOL:
        out["reason"] = "the file does not state lmidsl's SDP: " + (
            "its blocks do not match the LMIs" if identity is None else f"at a random point it differs by "
                                                                        f"{identity:.1e} (relative)")
        return out
    own = model.solve(solver, **options)
    out["lmidsl_status"], out["lmidsl_optimum"] = own.status, own.objective
    try:
        value, _ = solve_sdpa_cvxpy(problem, accept_inaccurate=True)
    except LmidslError as exc:
        if own.status.startswith("infeasible") and "infeasible" in str(exc):
            out["holds"] = True        # the same SDP, and both routes find it infeasible
            out["file_optimum"] = None
            out["reason"] = f"infeasible by both routes ({exc}; lmidsl: {own.status})"
            return out
        out["reason"] = (f"the file states lmidsl's SDP exactly (identity {identity:.1e}), but {exc} "
                         f"(lmidsl as written: {own.status}); lmidsl solves it conditioned, which an SDP "
                         f"file does not carry")
        return out
    out["file_optimum"] = value
    if instance.theorem.objective is None:       # feasibility: both routes find a point
        out["lmidsl_certified"] = bool(own.ok and own.lmis_hold)
        out["holds"] = out["lmidsl_certified"]
        if not out["holds"]:
            out["reason"] = f"the file gives a point, lmidsl's own solve no certified one ({own.status})"
        return out
    if not own.ok or own.objective is None:
        out["reason"] = (f"lmidsl's own solve of the SDP as written gives no point ({own.status}): lmidsl "
                         f"solves it conditioned (a congruence and a variable scaling, under which the "
                         f"margin means another SDP), which an SDP file does not carry; the file's "
                         f"optimum {value:.8g} cannot be compared")
        return out
    rel = abs(value - own.objective) / max(abs(own.objective), 1e-12)
    out["relative_difference"] = rel
    out["holds"] = rel <= OPTIMUM_RTOL
    if not out["holds"]:
        out["reason"] = f"the file's optimum differs by {rel:.1e} (more than {OPTIMUM_RTOL:g})"
    return out


def _identity_error(problem: SDPAProblem, x: np.ndarray, model) -> float | None:
    """max relative difference between the file at x and lmidsl's problem at the model's
    assigned point: cᵀx against the objective, the blocks' sorted eigenvalues against the
    LMIs' −N − εI (None: not the same number of eigenvalues)."""
    objective = 0.0 if model.objective is None else float(model.expression_value(model.objective))
    errors = [abs(float(problem.c @ x) - objective) / max(1.0, abs(objective))]
    theorem = model.instance.theorem
    strict = {lmi.label: lmi.strict for lmi in theorem.lmis}
    bounds = [np.atleast_1d(model.expression_value(model.variable_for(d.symbol, None)))
              for d in theorem.var_decl.values() if d.extra.get("nonneg")]      # x >= 0 rows
    want = np.sort(np.concatenate(bounds + [
        np.linalg.eigvalsh(-N - (model.margin if strict[key[0]] else 0.0) * np.eye(len(N)))
        for key, N in model.lmi_values().items()]))
    got = np.sort(np.concatenate([np.linalg.eigvalsh((B + B.T) / 2) if size > 0 else np.diag(B)
                                  for B, size in zip(blocks_at(problem, x), problem.blocks)]))
    if len(got) != len(want):
        return None
    errors.append(float(np.max(np.abs(got - want))) / max(1.0, float(np.max(np.abs(want)))))
    return max(errors)


def export(instance: Instance, fmt: str, path: str | Path, margin: float | None = None) -> dict:
    """Write ``instance``'s SDP to ``path`` in ``fmt`` (sdpa, cbf, json: the map alone); the
    map is also written next to an SDPA or CBF file as ``<path>.map.json``.  Returns the map."""
    if fmt not in FORMATS:
        raise InputError(f"--format {fmt}: one of {', '.join(FORMATS)}")
    path = Path(path)
    applied = apply_scaling(instance, "auto")       # as `lmidsl solve` compiles it
    model = _picos_model(applied.scaled, margin)
    mapping = export_map(model)
    mapping["scaling"] = [{"signal": r.signal, "factors": list(map(float, r.factors))}
                          for r in applied.records]
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        if fmt == "json":
            path.write_text(json.dumps(mapping, indent=2, default=float))
            return mapping
        sdpa_path = path if fmt == "sdpa" else path.with_name(path.name + ".tmp.dat-s")
        if sdpa_path.suffix != ".dat-s":
            raise InputError(f"-o {path}: an SDPA sparse file must end in .dat-s")
        model.problem.options.verbosity = 0
        with warnings.catch_warnings():      # PICOS' writer uses its own deprecated accessors
            warnings.simplefilter("ignore", DeprecationWarning)
            model.problem.write_to_file(str(sdpa_path))
        if fmt == "cbf":
            if path.suffix != ".cbf":
                raise InputError(f"-o {path}: a CBF file must end in .cbf")
            problem = read_sdpa(sdpa_path.read_text())
            sdpa_path.unlink()
            path.write_text(write_cbf(problem))
        mapping["file"] = str(path)
        mapping["format"] = fmt
        Path(str(path) + ".map.json").write_text(json.dumps(mapping, indent=2, default=float))
    except OSError as exc:
        raise InputError(f"-o {path}: {exc.strerror}") from None
    return mapping


def read_back(path: str | Path) -> SDPAProblem:
    """Read an exported file (by its suffix)."""
    path = Path(path)
    text = path.read_text()
    return read_cbf(text) if path.suffix == ".cbf" else read_sdpa(text)


__all__ = ["FORMATS", "SDPAProblem", "export", "export_map", "read_back", "read_sdpa", "read_cbf",
           "write_cbf", "solve_sdpa_cvxpy", "variables_from_x", "x_from_variables", "check_round_trip"]
