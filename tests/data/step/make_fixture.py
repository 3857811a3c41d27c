"""Writes fixture-in.step: two named solids, written by Open CASCADE (its STEP writer, XCAF names).

Run once with the OCP binding (``pip install cadquery-ocp-novtk``), not by the suite; the file it
writes is committed beside it. The file is in inches so the import's units come from the file:
BLOCK 4 x 3 x 1 in (101.6 x 76.2 x 25.4 mm), PEG a cylinder of radius 1 in, 2.5 in high
(50.8 x 50.8 x 63.5 mm), standing 6 in from the block along X.
"""

from pathlib import Path

from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.STEPCAFControl import STEPCAFControl_Writer
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Controller
from OCP.TCollection import TCollection_ExtendedString
from OCP.TDataStd import TDataStd_Name
from OCP.TDocStd import TDocStd_Document
from OCP.XCAFDoc import XCAFDoc_DocumentTool

doc = TDocStd_Document(TCollection_ExtendedString("XmlOcaf"))
shapes = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
block = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 4.0, 3.0, 1.0).Shape()
peg = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(6.0, 1.5, 0), gp_Dir(0, 0, 1)), 1.0, 2.5).Shape()
for shape, name in ((block, "BLOCK"), (peg, "PEG")):
    TDataStd_Name.Set_s(shapes.AddShape(shape, False), TCollection_ExtendedString(name))
# the model's numbers are inches (the document's unit, in metres); the file is written in inches
XCAFDoc_DocumentTool.SetLengthUnit_s(doc, 0.0254)
STEPControl_Controller.Init_s()  # the writer reads its parameters from here
Interface_Static.SetCVal_s("write.step.unit", "INCH")
writer = STEPCAFControl_Writer()
writer.SetNameMode(True)
writer.Transfer(doc, STEPControl_AsIs)
out = Path(__file__).with_name("fixture-in.step")
assert writer.Write(str(out)) == IFSelect_RetDone
