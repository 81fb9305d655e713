"""Helpers of the command-line tests: tiny scenarios (a coarse patrol boat, 30-min steps)
so that a whole thermal run takes seconds."""

from pathlib import Path

#: A 56 m patrol boat at 5.6 m edges (~430 triangles), 30-min steps, a few days: the
#: coarsest run that still exercises every stage. Nothing here is a physical claim.
TINY = """\
name = "{name}"
[time]
season = "{season}"
output_interval = 3600
[ship]
builtin = "patrol_boat"
edge_length = 5.6
mooring_position = [90.0, 30.0]
[solver]
time_step = 1800
spinup_max_days = {days}
spinup_tolerance = {tolerance}
rays_per_face = 16
samples_per_face = 4
[background]
size_px = 100
[outputs]
checkpoint_interval = 3600
formats = {formats}
"""


def write_tiny(folder, name="tiny", season="summer", days=2, tolerance=0.01,
               formats=("csv", "json"), extra="") -> Path:
    """Write a tiny scenario file; ``mooring_position`` [90, 30] m is harbour water of the
    100-pixel synthetic port (its default berth scaled to that size)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    fmts = "[" + ", ".join(f'"{f}"' for f in formats) + "]"
    path = folder / f"{name}.toml"
    path.write_text(TINY.format(name=name, season=season, days=days, tolerance=tolerance,
                                formats=fmts) + extra)
    return path


