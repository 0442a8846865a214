"""Tables in the form results.md shows them: numbers formatted alike in every part, markdown tables, and the
tables fnopt bench prints, read back into rows."""

import re
import statistics

# A row of a table fnopt bench prints: "  32^2  1.23  4.56 ...".
BENCH_ROW = re.compile(r"^\s*(\d+)\^2\s+(.*)$")


def fnum(text):
    """The number in a table cell; None for an empty or non-numeric cell."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def fmt(value, digits=3):
    """A number as the tables show it: digits significant figures, "—" for none."""
    if value is None:
        return "—"
    if value == 0:
        return "0"
    if 10 ** digits - 0.5 <= abs(value) < 1e7:
        return "%.0f" % value  # 1670, not 1.67e+03
    return "%.*g" % (digits, value)


def mean(values):
    """The mean of the values that are not None; None when there are none."""
    values = [v for v in values if v is not None]
    return statistics.mean(values) if values else None


def mean_cell(rows, column):
    """The mean of a numeric column over rows as the tables show it ("—" where there is none)."""
    return fmt(mean(fnum(r[column]) for r in rows))


def max_cell(rows, column):
    """The largest value of a numeric column over rows (an empty cell counting 0) as the tables show it."""
    return fmt(max((fnum(r[column]) or 0.0) for r in rows))


def unique(values):
    """The values without repeats, in the order they first come."""
    return list(dict.fromkeys(values))


def markdown_table(header, rows):
    """A markdown table of the header and rows."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def bench_table(text):
    """The table fnopt bench printed: (its header line, None when there is none; its rows, each starting with
    the grid as "32²")."""
    lines = text.splitlines()
    header_line = next((l for l in lines if l.strip().startswith("res")), None)
    rows = [[m.group(1) + "²"] + m.group(2).split() for m in (BENCH_ROW.match(l) for l in lines) if m]
    return header_line, rows
