"""Render a snapshot of an efsi run with ParaView (pvbatch): the last time step of
fields/fields_image.xdmf (the image-data XDMF), sliced at mid-z, coloured by pressure, with
the phi = 0.5 contour of each body. Used for docs/img/paraview_body_translation.png:

    efsi run cases/body_translation --output out/bt --set time.end_time=0.25 \
        --set output.fields_interval=0.25
    xvfb-run -a pvbatch scripts/paraview_snapshot.py out/bt/fields/fields_image.xdmf shot.png

(Debian: apt-get install paraview python3-paraview xvfb; pvbatch needs an X display.)"""
import sys
from paraview.simple import *
src, png = sys.argv[1], sys.argv[2]
r = Xdmf3ReaderS(FileName=[src])
t = r.TimestepValues[-1]
r.UpdatePipeline(t)
b = r.GetDataInformation().GetBounds()
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1000, 520]
view.ViewTime = t
view.OrientationAxesVisibility = 0
s = Slice(Input=r)
s.SliceType.Origin = [0, 0, 0.5 * (b[4] + b[5])]
s.SliceType.Normal = [0, 0, 1]
d = Show(s, view)
d.Representation = "Surface"
ColorBy(d, ("CELLS", "pressure"))
d.RescaleTransferFunctionToDataRange(True, False)
d.SetScalarBarVisibility(view, True)
cp = CellDatatoPointData(Input=s)
colours = [[1, 1, 1], [0, 0, 0], [1, 0.1, 0.1], [0.1, 0.8, 0.1]]
bodies = [r.CellData.GetArray(i).GetName() for i in range(len(r.CellData))]
bodies = [n for n in bodies if n.startswith("phi_")]
for name, colour in zip(bodies, colours * 4):
    c = Contour(Input=cp, ContourBy=["POINTS", name], Isosurfaces=[0.5])
    cd = Show(c, view)
    ColorBy(cd, None)
    cd.AmbientColor = colour
    cd.DiffuseColor = colour
    cd.LineWidth = 3
cx, cy = 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3])
view.CameraPosition = [cx, cy, 10]
view.CameraFocalPoint = [cx, cy, 0]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelProjection = 1
view.CameraParallelScale = 0.55 * (b[3] - b[2])
SaveScreenshot(png, view, ImageResolution=[1000, 520])
print("saved", png, "t =", t)
