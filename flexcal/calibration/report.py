"""The calibration's figures (PNG, matplotlib) and its self-contained report.html.

Figure numbers follow the reference report: 6 resistance vs firmware angle, 7 resistance
vs photo angle, 8 the error, 11 and 12 the pressure experiment, 13 the knuckle-pressure
term, 14 the model error against the measured error; plus residuals and validation.
"""

from __future__ import annotations

import base64
import html
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from flexcal.calibration import reference  # noqa: E402
from flexcal.calibration.models import pressure_shape  # noqa: E402

_DPI = 110


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=_DPI)
    plt.close(fig)
    return path


def _by_step(ax, used, x, y, label):
    ax.scatter(used[x], used[y], s=10, color="0.65", label="each photo", zorder=1)
    g = used.groupby("step")
    ax.errorbar(g[x].mean(), g[y].mean(), xerr=g[x].std(), yerr=g[y].std(), fmt="o", color="C0", ms=4,
                capsize=3, label=f"{label}: mean ± sd across trials", zorder=2)


def _line(ax, xs, slope, intercept, **kw):
    xs = np.array([np.min(xs), np.max(xs)])
    ax.plot(xs, slope * xs + intercept, **kw)


def _step_figure(path, data, x, y, label, lines, *, xlabel, ylabel, title):
    """Each photo, the per-step mean ± sd across trials, and lines (slope, intercept, plot style)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    _by_step(ax, data, x, y, label)
    for slope, intercept, style in lines:
        _line(ax, data[x], slope, intercept, **style)
    ax.set(xlabel=xlabel, ylabel=ylabel, title=title)
    ax.legend(fontsize=8)
    return _save(fig, path)


def make_figures(result, out_dir) -> dict:
    """Write the PNG figures into ``out_dir``; returns {key: path}."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    r = result
    used = r.used
    figs = {}
    a = used["angle_actual_deg"].to_numpy(float)

    figs["fig06"] = _step_figure(
        out / "fig06_resistance_vs_firmware_angle.png", used, "angle_measured_deg", "resistance_ohm", "firmware angle",
        [(r.eq16.slope, r.eq16.intercept, dict(color="C1", label=f"fit: R = {r.eq16.slope:.1f} θ + {r.eq16.intercept:.0f}")),
         (*reference.EQ16, dict(color="k", ls=":", label="reference eq 16: R = 577.9 θ + 31 250"))],
        xlabel="firmware (measured) angle [deg]", ylabel="resistance [Ω]",
        title="Fig. 6: resistance vs firmware angle (eq 16)")
    figs["fig07"] = _step_figure(
        out / "fig07_resistance_vs_photo_angle.png", used, "angle_actual_deg", "resistance_ohm", "photo angle",
        [(r.eq17.slope, r.eq17.intercept, dict(color="C1", label=f"ODR: R = {r.eq17.slope:.1f} θ + {r.eq17.intercept:.0f}")),
         (r.eq17_ols.slope, r.eq17_ols.intercept,
          dict(color="C2", ls="--", label=f"OLS: R = {r.eq17_ols.slope:.1f} θ + {r.eq17_ols.intercept:.0f}")),
         (*reference.EQ17, dict(color="k", ls=":", label="reference eq 17: R = 587.1 θ + 34 400"))],
        xlabel="photo (actual) angle [deg]", ylabel="resistance [Ω]", title="Fig. 7: resistance vs photo angle (eq 17)")
    figs["fig08"] = _step_figure(
        out / "fig08_error_vs_angle.png", used.assign(error_ohm=used["resistance_ohm"].to_numpy(float) - r.eq16(a)),
        "angle_actual_deg", "error_ohm", "error",
        [(r.eq18["slope"], r.eq18["intercept"], dict(
            color="C1", label=f"eq 17 − eq 16: R_err = {r.eq18['slope']:.1f} θ + {r.eq18['intercept']:.0f}")),
         (*reference.EQ18, dict(color="k", ls=":", label="reference eq 18: R_err = 9.2 θ + 3 150"))],
        xlabel="photo (actual) angle [deg]", ylabel="R − eq 16(θ) [Ω]", title="Fig. 8: error of the factory mapping (eq 18)")

    if r.pressure is not None:
        p = r.pressure
        t = p.table
        for key, col, f, refl, ylabel, title, name in (
                ("fig11", "angle_deg", p.angle_fit, reference.ANGLE_VS_PRESSURE, "bend angle [deg]",
                 "Fig. 11: angle vs pressure", "fig11_angle_vs_pressure.png"),
                ("fig12", "resistance_ohm", p.resistance_fit, reference.RESISTANCE_VS_PRESSURE, "resistance [Ω]",
                 "Fig. 12: resistance vs pressure", "fig12_resistance_vs_pressure.png")):
            fig, ax = plt.subplots(figsize=(6.4, 4.4))
            g = t.groupby("mass_g")
            ax.scatter(t["pressure_psi"], t[col], s=10, color="0.65", label="each repeat")
            ax.errorbar(g["pressure_psi"].mean(), g[col].mean(), yerr=g[col].std(), fmt="o", capsize=3,
                        label="mean ± sd per mass")
            _line(ax, t["pressure_psi"], f.slope, f.intercept, color="C1",
                  label=f"fit: {f.slope:.4g} p + {f.intercept:.5g}")
            _line(ax, t["pressure_psi"], *refl, color="k", ls=":", label=f"reference: {refl[0]:g} p + {refl[1]:g}")
            ax.set(xlabel=f"pressure [psi] (contact area {p.contact_area_in2:g} in²)", ylabel=ylabel, title=title)
            ax.legend(fontsize=8)
            figs[key] = _save(fig, out / name)

    rm, pf = r.reference_model, r.physical_fit
    th = np.linspace(max(0.0, a.min()), a.max(), 200)
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.plot(th, rm["pressure_k_ohm_per_psi"] * pressure_shape(th, rm["deg_per_psi"]), color="C1",
            label=f"reference form: k = {rm['pressure_k_ohm_per_psi']:.1f} ± {rm['pressure_k_se']:.1f} Ω/psi")
    ax.plot(th, pf["pressure_k_ohm_per_psi"] * pressure_shape(th, pf["deg_per_psi"]), color="C2", ls="--",
            label=f"physical fit: k = {pf['pressure_k_ohm_per_psi']:.1f} ± {pf['pressure_k_se']:.1f} Ω/psi")
    ax.set(xlabel="bend angle [deg]", ylabel="R_pressure [Ω]",
           title="Fig. 13: knuckle-pressure term k·p(θ)·θ / cos((π−θ)/2)")
    ax.legend(fontsize=8)
    figs["fig13"] = _save(fig, out / "fig13_pressure_term.png")

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.scatter(rm["angle_deg"], rm["e_measured_ohm"], s=12, label="E_measured = R_actual − R_measured (eq 22)")
    ax.scatter(rm["angle_deg"], rm["e_model_ohm"], s=12, marker="x",
               label="E_model = R_actual − R_total (eq 21)")
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set(xlabel="photo (actual) angle [deg]", ylabel="error [Ω]",
           title=f"Fig. 14: the pressure term removes {100 * rm['share_of_error_removed']:.0f} % of the mean |error|")
    ax.legend(fontsize=8)
    figs["fig14"] = _save(fig, out / "fig14_model_vs_measured_error.png")

    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for trial, g in used.groupby("trial"):
        ax.scatter(g["angle_actual_deg"], g["resistance_ohm"] - r.eq17(g["angle_actual_deg"]), s=12, label=trial)
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set(xlabel="photo (actual) angle [deg]", ylabel="residual [Ω]", title="Residuals of eq 17 (ODR), by trial")
    ax.legend(fontsize=7, ncol=2)
    figs["residuals"] = _save(fig, out / "residuals_eq17.png")

    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    ve = r.validation_errors.merge(used[["trial", "image", "angle_actual_deg"]], on=["trial", "image"])
    for i, (name, g) in enumerate(ve.groupby("mapping", sort=False)):
        ax.scatter(g["angle_actual_deg"], g["error_deg"], s=12, color=f"C{i}", label=name)
    ax.axhline(0, color="0.5", lw=0.8)
    how = r.validation["validation"].iloc[-1] if len(r.validation) else ""
    ax.set(xlabel="photo (actual) angle [deg]", ylabel="angle error [deg]",
           title=f"Angle error of each mapping ({how})")
    ax.legend(fontsize=8)
    figs["validation"] = _save(fig, out / "validation_angle_error.png")
    return figs


def _img(path) -> str:
    data = base64.b64encode(Path(path).read_bytes()).decode()
    return f'<img src="data:image/png;base64,{data}" alt="{html.escape(Path(path).name)}">'


def _cell(c) -> str:
    c = str(c)
    return c if c.startswith("<img ") else html.escape(c)


def _table(rows, header) -> str:
    head = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{_cell(c)}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _se(x) -> str:
    """A standard error to two significant digits, without exponent notation."""
    if not np.isfinite(x) or x == 0:
        return f"{x:g}"
    digits = max(0, 1 - int(np.floor(np.log10(abs(x)))))
    return f"{round(x, digits):.{digits}f}"


def _eq(slope, intercept, se_s=None, se_i=None, x="θ", y="R", unit="Ω") -> str:
    s = f"{y} = {slope:.4g}" + (f" (± {_se(se_s)})" if se_s is not None else "") + f" {x}"
    s += f" {'+' if intercept >= 0 else '−'} {abs(intercept):.5g}" + (f" (± {_se(se_i)})" if se_i is not None else "")
    return s + f" {unit}"


def _thumb(path, width=240) -> str:
    """An overlay as an embedded JPEG thumbnail ('' when it is not there)."""
    import cv2

    # (a photo that could not be read has no overlay; OpenCV would warn on stderr)
    img = cv2.imread(str(path), cv2.IMREAD_REDUCED_COLOR_4) if Path(path).is_file() else None
    if img is None:
        return ""
    h = max(1, int(round(img.shape[0] * width / img.shape[1])))
    ok, buf = cv2.imencode(".jpg", cv2.resize(img, (width, h), interpolation=cv2.INTER_AREA),
                           [cv2.IMWRITE_JPEG_QUALITY, 80])
    return f'<img class="thumb" src="data:image/jpeg;base64,{base64.b64encode(buf).decode()}" alt="overlay">' if ok else ""


def write_report(result, data: dict, figs: dict, path, *, overlays_dir=None, overlays: dict | None = None) -> None:
    """The self-contained report.html (figures, and the overlays of excluded photos, embedded).

    ``overlays`` maps a photo's path (as in the pairs table) to its overlay file.
    """
    r = result
    rows = [
        ("15", "R vs firmware angle, first setup", "—", _eq(*reference.EQ15)),
        ("16", "R vs firmware (measured) angle", _eq(r.eq16.slope, r.eq16.intercept, r.eq16.slope_se,
                                                      r.eq16.intercept_se), _eq(*reference.EQ16)),
        ("17", "R vs photo (actual) angle, ODR", _eq(r.eq17.slope, r.eq17.intercept, r.eq17.slope_se,
                                                      r.eq17.intercept_se), _eq(*reference.EQ17)),
        ("17", "… same, OLS", _eq(r.eq17_ols.slope, r.eq17_ols.intercept, r.eq17_ols.slope_se,
                                   r.eq17_ols.intercept_se), _eq(*reference.EQ17)),
        ("18", "error = (17) − (16)", _eq(r.eq18["slope"], r.eq18["intercept"], r.eq18["slope_se"],
                                          r.eq18["intercept_se"], y="R_err"), _eq(*reference.EQ18, y="R_err")),
    ]
    if r.pressure is not None:
        p = r.pressure
        rows += [
            ("—", "angle vs pressure", _eq(p.angle_fit.slope, p.angle_fit.intercept, p.angle_fit.slope_se,
                                           p.angle_fit.intercept_se, x="p", y="θ", unit="°"),
             _eq(*reference.ANGLE_VS_PRESSURE, x="p", y="θ", unit="°")),
            ("—", "resistance vs pressure", _eq(p.resistance_fit.slope, p.resistance_fit.intercept,
                                                p.resistance_fit.slope_se, p.resistance_fit.intercept_se, x="p"),
             _eq(*reference.RESISTANCE_VS_PRESSURE, x="p")),
            ("19", "ratio of the slopes", f"R_pressure = {p.ratio_ohm_per_deg:.4g} (± {_se(p.ratio_se)}) θ Ω",
             f"R_pressure = {reference.EQ19_SLOPE:g} θ Ω"),
        ]
    rm, pf = r.reference_model, r.physical_fit
    rows += [
        ("20", "R_bending (eq 16) + k·p(θ)·θ/cos((π−θ)/2), reference form",
         f"k = {rm['pressure_k_ohm_per_psi']:.4g} ± {_se(rm['pressure_k_se'])} Ω/psi; removes "
         f"{100 * rm['share_of_error_removed']:.0f} % of mean |error|", "removes about half of the error"),
        ("20", "physical model, all terms fitted",
         f"R = {pf['offset_ohm']:.5g} (± {_se(pf['offset_se'])}) + {pf['slope_ohm_per_deg']:.4g} "
         f"(± {_se(pf['slope_se'])}) θ + {pf['pressure_k_ohm_per_psi']:.4g} (± {_se(pf['pressure_k_se'])})"
         "·p(θ)·θ/cos((π−θ)/2)",
         "—"),
    ]
    val_rows = [(v["mapping"], f"{v['rmse_deg']:.2f}", f"{v['bias_deg']:+.2f}", f"{v['max_abs_deg']:.2f}", v["n"],
                 v["validation"]) for v in data["validation"]]
    excl = data["pairs"]["excluded"]
    overlays = overlays or {}
    excl_rows = [(e["trial"], Path(e["image"]).name, e["reason"],
                  _thumb(overlays[e["image"]]) if e["image"] in overlays else "") for e in excl]
    inputs = data["inputs"]
    in_rows = [(t["name"], t["log"], t["log_sha256"][:12], len(t["images"]), t.get("frames") or "—")
               for t in inputs["trials"]]
    fig_html = "".join(f"<figure>{_img(p)}</figure>" for p in figs.values())
    ov = f'<p>Overlays of every photo, and a contact sheet: <code>{html.escape(str(overlays_dir))}</code></p>' \
        if overlays_dir else ""
    notes = "".join(f"<li>{html.escape(n)}</li>" for n in data["notes"]) or "<li>none</li>"
    doc = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>flexcal calibration report</title>
<style>
body {{ font-family: system-ui, sans-serif; max-width: 1100px; margin: 2em auto; color: #222; }}
table {{ border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 0.9em; }}
td, th {{ border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }}
th {{ background: #f2f2f2; }} figure {{ display: inline-block; margin: 0.3em; }} img {{ max-width: 520px; }} img.thumb {{ max-width: 240px; }}
.big {{ font-size: 1.15em; }}
</style></head><body>
<h1>flexcal calibration report</h1>
<p>flexcal {html.escape(str(data['flexcal_version']))}, {html.escape(data['created'])}.
{data['pairs']['used']} of {data['pairs']['total']} photo/reading pairs used.
Recommended mapping: <b>{html.escape(data['recommended_mapping'])}</b> (calibration.json, flexcal_calibration.h).</p>
<h2>Corrected angle: validation</h2>
<p class="big">Angle error in degrees against the photo angles.</p>
{_table(val_rows, ["mapping", "RMSE [deg]", "bias [deg]", "max |error| [deg]", "pairs", "how"])}
<h2>Fits beside the reference's</h2>
<p>θ in degrees, R in ohm, p in psi; ± are standard errors.</p>
{_table(rows, ["eq", "relation", "this calibration", "reference"])}
<h2>Figures</h2>
{fig_html}
<h2>Excluded pairs ({len(excl)})</h2>
{_table(excl_rows, ["trial", "photo", "why", "overlay"]) if excl_rows else "<p>none</p>"}
{ov}
<h2>Notes</h2><ul>{notes}</ul>
<h2>Inputs</h2>
{_table(in_rows, ["trial", "log", "sha256", "photos", "frames"])}
<p>Parameters: <code>{html.escape(str(data['parameters']))}</code></p>
</body></html>
"""
    Path(path).write_text(doc)
