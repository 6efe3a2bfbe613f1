"""Opens IGES files with FreeCAD's headless importer (run by freecadcmd; .ci/checks/cad.sh).

The files and their expected face counts come in NENDO_IGES as "PATH=FACES;PATH=FACES;...".
Each is inserted into a new document with Import.insert, as FreeCAD's GUI would open it, and
read with Part.read; the faces of both are counted and the shapes checked valid. Prints one
line per file and FREECAD_IGES_OK at the end; any failure (or a crash of the importer, which
ends the process) leaves that line out, and the caller fails.
"""

import os
import sys

import FreeCAD
import Import
import Part

ok = True
for item in os.environ["NENDO_IGES"].strip(";").split(";"):
    path, want = item.rsplit("=", 1)
    shape = Part.Shape()
    shape.read(path)
    doc = FreeCAD.newDocument("nendo_check")
    Import.insert(path, doc.Name)
    inserted = sum(len(o.Shape.Faces) for o in doc.Objects if hasattr(o, "Shape"))
    FreeCAD.closeDocument(doc.Name)
    good = len(shape.Faces) == int(want) and inserted == int(want) and shape.isValid()
    ok = ok and good
    print(f"freecad_iges: FreeCAD {FreeCAD.Version()[0]}.{FreeCAD.Version()[1]}: {path}: Import.insert "
          f"{inserted} faces, Part.read {len(shape.Faces)} faces valid {shape.isValid()}"
          f" (expected {want}){'' if good else ' WRONG'}")
    sys.stdout.flush()
if ok:
    print("\nFREECAD_IGES_OK")
