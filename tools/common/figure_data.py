"""What a tool's figure draws, as numbers: with $TETCONTACT_FIGURE_DATA set, `save` writes
OUT.png.json beside the PNG — per axes its title and labels, each line's label and points, each
image's array and each text — so that a test reads what was drawn (the wrong numbers fail it,
not only a missing file). Unset (a user's run), nothing more is written.

    from tools.common import figure_data
    figure_data.save(fig, out)   # after fig.savefig(...)"""
import json
import os


def _numbers(values):
    return [float(v) for v in values]


def describe(fig):
    """The figure's axes as plain data."""
    axes = []
    for ax in fig.axes:
        axes.append({
            "title": ax.get_title(),
            "xlabel": ax.get_xlabel(),
            "ylabel": ax.get_ylabel(),
            "lines": [{"label": line.get_label(), "x": _numbers(line.get_xdata()),
                       "y": _numbers(line.get_ydata())} for line in ax.get_lines()],
            "images": [[_numbers(row) for row in im.get_array()] for im in ax.get_images()],
            "texts": [{"text": t.get_text(), "x": float(t.get_position()[0]),
                       "y": float(t.get_position()[1])} for t in ax.texts],
        })
    return {"axes": axes}


def save(fig, out):
    """Writes OUT.json (OUT the PNG's path) when $TETCONTACT_FIGURE_DATA is set."""
    if not os.environ.get("TETCONTACT_FIGURE_DATA"):
        return
    with open(out + ".json", "w") as f:
        json.dump(describe(fig), f)
