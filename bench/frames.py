"""The bench scripts' reading of a case's last dump frame, and how far two runs' last frames part.
The scripts' Python finds it on PYTHONPATH, which bench/common.sh sets."""


def last_frame(case):
    """The columns and, by id, the values of the last frame of CASE/dumps/dump.txt."""
    lines = open(f"{case}/dumps/dump.txt").read().split("ITEM: TIMESTEP")[-1].splitlines()
    cols = lines[8].split()[2:]
    return cols, {int(float(v.split()[0])): [float(x) for x in v.split()] for v in lines[9:]}


def largest_difference(cols, ref, other):
    """The largest relative difference of any position or velocity of OTHER against REF (frames as
    last_frame gives them), below 1 mm and 1 um/s taken against those floors."""
    ix = [cols.index(c) for c in ("x", "y", "z", "vx", "vy", "vz")]
    return max(abs(ref[i][k] - other[i][k]) / max(abs(ref[i][k]), 1e-3 if k < ix[3] else 1e-6) for i in ref for k in ix)
