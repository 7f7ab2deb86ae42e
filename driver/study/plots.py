"""The trend table as one figure: each comparison's ratio against the thesis' direction."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

from rubberfriction.driver.study.trends import TrendRow


def plot_trends(rows: list[TrendRow], path: Path, subtitle: str) -> Path:
    """Horizontal bars of log10(ratio), one per comparison, grouped by trend: green where the
    sign agrees with the thesis, red where it does not, grey for information-only pairs; the
    error bar is the samples' spread; a star marks the thesis' ratio where it gives one."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels, values, errors, colours, stars = [], [], [], [], []
    for r in rows:
        for i, c in enumerate(r.comparisons):
            labels.append(f"{r.key}: {c.label}")
            ok = math.isfinite(c.ratio) and c.ratio > 0
            values.append(math.log10(c.ratio) if ok else 0.0)
            errors.append(c.uncertainty / math.log(10) if math.isfinite(c.uncertainty) else 0.0)
            colours.append("0.7" if not c.counts or not ok else
                           "tab:green" if c.sign else "tab:red")
            stars.append(math.log10(r.thesis_ratio) if i == 0 and r.thesis_ratio else None)
    fig, ax = plt.subplots(figsize=(9, 0.42 * len(labels) + 1.6))
    y = list(range(len(labels)))[::-1]
    ax.barh(y, values, xerr=errors, color=colours, capsize=3)
    for yi, s in zip(y, stars):
        if s is not None:
            ax.plot([s], [yi], "k*", ms=10)
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_yticks(y)
    ax.set_yticklabels(labels, fontsize=8)
    ax.set_xlabel("log10(ratio)  (green: sign as in the thesis, red: opposite, grey: "
                  "information or no value; star: thesis' ratio)", fontsize=8)
    ax.set_title(f"thesis trends: {sum(r.verdict == 'agrees' for r in rows)} of {len(rows)} "
                 "agree in sign\n" + "\n".join(textwrap.wrap(subtitle, 90)), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
