"""gfmd's constants, read from the library's one table (include/gfmd/constants.tbl in the source
tree, or the copy installed beside this package), so that they are never retyped."""
from pathlib import Path

_HERE = Path(__file__).resolve().parent


def _table():
    for path in (_HERE / "constants.tbl", _HERE.parent.parent / "include" / "gfmd" / "constants.tbl"):
        if path.exists():
            return path
    raise ImportError("gfmd: constants.tbl not found beside the package or in the source tree")


def read():
    """{name: value} of every enum value and real constant, and {status value: description}."""
    values, statuses = {}, {}
    enum = None
    for line in _table().read_text().splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        parts = [p.strip() for p in line.split("|")]
        if parts[0] == "enum":
            enum = parts[1]
        elif parts[0] == "value":
            values[parts[1]] = int(parts[2])
            if enum == "gfmd_status_code":
                statuses[int(parts[2])] = parts[3]
        elif parts[0] == "alias":
            values[parts[1]] = values[parts[2]]
        elif parts[0] == "real":
            values[parts[1]] = float(parts[2])
        else:
            raise ImportError(f"gfmd: malformed line in {_table()}: {line}")
    return values, statuses
