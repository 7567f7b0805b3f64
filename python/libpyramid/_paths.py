"""What a path given to open() names: a pyramid file, a region set, or a planet directory.

* A file: a residual or ortho pyramid file; a region set when its index ``FILE.regions.json``
  lies beside it (doc/format.md 1.5).
* A region set's index (``NAME.dat.regions.json``), or a directory holding exactly one index
  and no ``NAME1.dat`` face.
* A planet directory: the six cube faces ``NAME1.dat`` .. ``NAME6.dat`` of the spherical
  preprocessors (each face a file or a set), NAME ``DEM`` or ``RGB`` unless given.
"""

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import List, Optional, Tuple

INDEX_SUFFIX = ".regions.json"
INDEX_FORMAT = "libpyramid region set"


@dataclass
class Region:
    """A region file of a set: its path and absolute root tile (level, tx, ty)."""
    path: Path
    root: Tuple[int, int, int]


@dataclass
class Resolved:
    """The files behind a path: `kind` is "file", "set" or "planet"."""
    kind: str
    path: Path
    main: Optional[Path] = None
    index: Optional[Path] = None
    regions: List[Region] = field(default_factory=list)
    faces: List[Path] = field(default_factory=list)
    name: Optional[str] = None


def _bad(path, problem):
    from ._errors import FileError
    from . import _capi
    return FileError(f"{path}: {problem}", _capi.ERROR_FILE, "file")


def read_index(index):
    """The main file and regions listed by a region set's index (checked by the C API at open)."""
    try:
        with open(index, "rb") as f:
            doc = json.load(f)
    except OSError as e:
        raise _bad(index, f"cannot read the region set's index: {e.strerror}") from None
    except ValueError as e:
        raise _bad(index, f"not a region set index: not JSON ({e})") from None
    if not isinstance(doc, dict) or doc.get("format") != INDEX_FORMAT or not isinstance(doc.get("main"), str):
        raise _bad(index, f"not a region set index (no \"format\": \"{INDEX_FORMAT}\" with a \"main\" file)")
    base = Path(index).parent
    regions = []
    for r in doc.get("regions", []):
        try:
            regions.append(Region(base / r["file"], tuple(int(v) for v in r["root"])))
        except (KeyError, TypeError, ValueError):
            raise _bad(index, f"a region without \"file\" and \"root\": {r!r}") from None
    return base / doc["main"], regions


def _faces(directory, name):
    names = [name] if name else ["DEM", "RGB"]
    for n in names:
        faces = [directory / f"{n}{i}.dat" for i in range(1, 7)]
        if any(f.exists() for f in faces):
            return n, faces
    return None, []


def resolve(path, name=None):
    """What `path` names (see the module doc); raises FileError when it names nothing readable."""
    p = Path(os.fspath(path))
    if p.is_dir():
        face_name, faces = _faces(p, name)
        indexes = sorted(p.glob("*" + INDEX_SUFFIX))
        if faces:
            missing = [str(f.name) for f in faces if not f.exists()]
            if missing:
                raise _bad(p, f"a planet directory without {', '.join(missing)}")
            return Resolved("planet", p, faces=faces, name=face_name)
        if len(indexes) == 1:
            main, regions = read_index(indexes[0])
            return Resolved("set", p, main=main, index=indexes[0], regions=regions)
        if indexes:
            raise _bad(p, f"a directory of {len(indexes)} region set indexes: name one of them")
        raise _bad(p, "a directory holding no pyramid (no NAME1..6.dat faces, no region set index)")
    if p.name.endswith(INDEX_SUFFIX):
        main, regions = read_index(p)
        return Resolved("set", p, main=main, index=p, regions=regions)
    index = p.with_name(p.name + INDEX_SUFFIX)
    if p.is_file() and index.is_file():
        main, regions = read_index(index)
        return Resolved("set", p, main=main, index=index, regions=regions)
    # A plain file, or a path the C API's open will report as missing.
    return Resolved("file", p, main=p)


def read_georeference(main):
    """The georeference sidecar ``MAIN.georef.json`` that preprocessDem writes beside a file made
    from a georeferenced input, as a dict, or None when there is none."""
    sidecar = Path(main).with_name(Path(main).name + ".georef.json")
    if not sidecar.is_file():
        return None
    try:
        with open(sidecar, "rb") as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        raise _bad(sidecar, f"unreadable georeference sidecar: {e}") from None
