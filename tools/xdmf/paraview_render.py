"""Render the first mode shape of a paraflex run with ParaView and check the picture.

Run with ParaView's Python (``pvpython``, headless: ``xvfb-run -a pvpython ...``; ``make
paraview-check`` does it)::

    pvpython tools/xdmf/paraview_render.py OUT_1_modes.xdmf -o mode1.png

Opens the time series with ParaView's XDMF3 reader, takes the first step (mode 1), warps the
mesh by the ``displacement`` vector (scaled so the largest displacement is a tenth of the
model's size), colours it by the displacement magnitude, writes the PNG, and checks it is not
blank: enough pixels differ from the background and they show several colours. Exit code 1
when the check fails.
"""
import argparse
import os
import sys

from paraview import simple as pv
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

BACKGROUND = [1.0, 1.0, 1.0]


def render(xdmf, png, size=(1200, 800)):
    reader = pv.Xdmf3ReaderS(FileName=[os.path.abspath(xdmf)])
    reader.UpdatePipelineInformation()
    first = reader.TimestepValues[0] if reader.TimestepValues else 0.0
    reader.UpdatePipeline(first)
    bounds = reader.GetDataInformation().GetBounds()
    diagonal = sum((bounds[2 * i + 1] - bounds[2 * i]) ** 2 for i in range(3)) ** 0.5
    largest = reader.PointData["displacement"].GetRange(-1)[1]
    if largest <= 0.0:
        raise SystemExit(f"{xdmf}: the first step has no displacement")
    warp = pv.WarpByVector(Input=reader, Vectors=["POINTS", "displacement"])
    warp.ScaleFactor = 0.1 * diagonal / largest
    view = pv.CreateView("RenderView")
    view.ViewSize = list(size)
    view.ViewTime = first
    view.Background = BACKGROUND
    view.OrientationAxesVisibility = 0
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    display = pv.Show(warp, view)
    pv.ColorBy(display, ("POINTS", "displacement", "Magnitude"))
    display.RescaleTransferFunctionToDataRange(True, False)
    display.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(pv.GetColorTransferFunction("displacement"), view)
    bar.Title, bar.ComponentTitle = "displacement", "magnitude (mode 1, normalised)"
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
    outline = pv.Show(reader, view)
    outline.SetRepresentationType("Wireframe")
    outline.AmbientColor = outline.DiffuseColor = [0.6, 0.6, 0.6]
    view.CameraPosition = [1.0, -1.5, 1.2]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera()
    pv.SaveScreenshot(png, view, ImageResolution=list(size))


def picture_stats(png):
    """Fraction of pixels differing from the background, and the number of distinct colours."""
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    image = reader.GetOutput()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars())[:, :3].astype(int)
    background = [round(255 * c) for c in BACKGROUND]
    drawn = (abs(pixels - background).sum(axis=1) > 30)
    colours = {tuple(p // 16) for p in pixels[drawn]}
    return drawn.mean(), len(colours)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("xdmf", help="OUT_<subcase>_modes.xdmf of a paraflex run")
    parser.add_argument("-o", "--output", required=True, help="PNG to write")
    args = parser.parse_args()
    render(args.xdmf, args.output)
    drawn, colours = picture_stats(args.output)
    print(f"{args.output}: {100 * drawn:.1f} % of the pixels drawn, {colours} colours")
    if drawn < 0.02 or colours < 8:
        print("the picture looks blank", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    # Skip the interpreter's teardown: under Xvfb, ParaView's OpenGL context release fails
    # with a GLX error at exit and would turn a passed check into exit code 1.
    os._exit(code)
