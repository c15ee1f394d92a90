"""Writes facet's own small OpenUSD stage and URDF robot into this folder (the guide's
examples). Run once: python models/make_stage_models.py (needs usd-core and trimesh).

* usd/stage.usda: a y-up stage: a ball whose variant set ``shadingVariant`` (red, blue)
  picks its UsdPreviewSurface, a subdivision cube (catmullClark cage), a payload
  (usd/parts/plinth.usda), a proxy-purpose box, a DistantLight and a camera
  ``renderCam`` moving over two seconds (time samples at 24 codes a second).
* arm/arm.urdf + arm/meshes/hand.stl: a small arm of boxes, a cylinder, spheres and a
  mesh found as ``package://arm/meshes/hand.stl``: revolute, fixed, prismatic and mimic
  joints, named and inline materials, a collision sphere on its base.
"""

from __future__ import annotations

from pathlib import Path

HERE = Path(__file__).resolve().parent

ARM = """<?xml version="1.0"?>
<robot name="arm">
  <material name="blue"><color rgba="0.15 0.3 0.8 1"/></material>
  <link name="base">
    <visual><geometry><box size="0.4 0.3 0.1"/></geometry><material name="blue"/></visual>
    <collision><geometry><sphere radius="0.25"/></geometry></collision>
  </link>
  <link name="upper">
    <visual><origin xyz="0 0 0.25"/><geometry><cylinder radius="0.05" length="0.5"/>
    </geometry><material name="red"><color rgba="0.8 0.15 0.1 1"/></material></visual>
  </link>
  <link name="fore">
    <visual><origin xyz="0.2 0 0"/><geometry><box size="0.4 0.06 0.06"/></geometry>
    </visual>
  </link>
  <link name="hand">
    <visual><geometry><mesh filename="package://arm/meshes/hand.stl"/></geometry></visual>
  </link>
  <link name="finger_a"><visual><geometry><sphere radius="0.03"/></geometry></visual></link>
  <link name="finger_b"><visual><geometry><sphere radius="0.03"/></geometry></visual></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="wrist" type="fixed"><parent link="fore"/><child link="hand"/>
    <origin xyz="0.4 0 0"/></joint>
  <joint name="slide" type="prismatic"><parent link="hand"/><child link="finger_a"/>
    <origin xyz="0 0.05 0"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.05" effort="1" velocity="1"/></joint>
  <joint name="slide_mimic" type="prismatic"><parent link="hand"/><child link="finger_b"/>
    <origin xyz="0 -0.05 0"/><axis xyz="0 -1 0"/>
    <limit lower="0" upper="0.05" effort="1" velocity="1"/>
    <mimic joint="slide" multiplier="1" offset="0"/></joint>
</robot>
"""


def _surface(stage, path: str, colour):
    from pxr import Sdf, UsdShade

    mat = UsdShade.Material.Define(stage, path)
    shader = UsdShade.Shader.Define(stage, f"{path}/Surface")
    shader.CreateIdAttr("UsdPreviewSurface")
    shader.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(colour)
    shader.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(0.35)
    mat.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    return mat


def write_stage(folder: Path) -> None:
    from pxr import Gf, Usd, UsdGeom, UsdLux, UsdShade

    (folder / "parts").mkdir(parents=True, exist_ok=True)
    plinth = Usd.Stage.CreateNew(str(folder / "parts" / "plinth.usda"))
    UsdGeom.SetStageUpAxis(plinth, UsdGeom.Tokens.y)
    box = UsdGeom.Cube.Define(plinth, "/Plinth/Box")
    UsdGeom.Xformable(box).AddScaleOp().Set(Gf.Vec3f(3.0, 0.2, 2.0))
    plinth.SetDefaultPrim(plinth.GetPrimAtPath("/Plinth"))
    plinth.GetRootLayer().Save()

    stage = Usd.Stage.CreateNew(str(folder / "stage.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    stage.SetTimeCodesPerSecond(24)
    stage.SetStartTimeCode(0)
    stage.SetEndTimeCode(48)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    red = _surface(stage, "/World/Looks/Red", (0.8, 0.1, 0.08))
    blue = _surface(stage, "/World/Looks/Blue", (0.1, 0.25, 0.8))
    ball = UsdGeom.Sphere.Define(stage, "/World/Ball")
    ball.CreateRadiusAttr(0.5)
    UsdGeom.Xformable(ball).AddTranslateOp().Set(Gf.Vec3d(-0.8, 0.6, 0))
    sets = ball.GetPrim().GetVariantSets().AddVariantSet("shadingVariant")
    for name, mat in (("red", red), ("blue", blue)):
        sets.AddVariant(name)
        sets.SetVariantSelection(name)
        with sets.GetVariantEditContext():
            UsdShade.MaterialBindingAPI.Apply(ball.GetPrim()).Bind(mat)
    sets.SetVariantSelection("blue")
    cube = UsdGeom.Mesh.Define(stage, "/World/SoftCube")
    corners = [(x, y, z) for x in (-0.4, 0.4) for y in (-0.4, 0.4) for z in (-0.4, 0.4)]
    cube.CreatePointsAttr(corners)
    cube.CreateFaceVertexCountsAttr([4] * 6)
    cube.CreateFaceVertexIndicesAttr([0, 1, 3, 2, 4, 6, 7, 5, 0, 4, 5, 1, 2, 3, 7, 6,
                                      0, 2, 6, 4, 1, 5, 7, 3])
    cube.CreateSubdivisionSchemeAttr("catmullClark")
    cube.CreateDisplayColorAttr([(0.9, 0.75, 0.3)])
    UsdGeom.Xformable(cube).AddTranslateOp().Set(Gf.Vec3d(0.8, 0.5, 0))
    plinth_ref = stage.DefinePrim("/World/Plinth")
    plinth_ref.GetPayloads().AddPayload("parts/plinth.usda")
    UsdGeom.Xformable(plinth_ref).AddTranslateOp().Set(Gf.Vec3d(0, -0.2, 0))
    proxy = UsdGeom.Cube.Define(stage, "/World/BallProxy")
    proxy.CreatePurposeAttr(UsdGeom.Tokens.proxy)
    proxy.CreateSizeAttr(1.0)
    UsdGeom.Xformable(proxy).AddTranslateOp().Set(Gf.Vec3d(-0.8, 0.6, 0))
    sun = UsdLux.DistantLight.Define(stage, "/World/Sun")
    sun.CreateIntensityAttr(3.0)
    sun.CreateNormalizeAttr(True)
    UsdGeom.Xformable(sun).AddRotateXYZOp().Set(Gf.Vec3f(-50, 30, 0))
    cam = UsdGeom.Camera.Define(stage, "/World/renderCam")
    cam.CreateFocalLengthAttr(35.0)
    cam.CreateClippingRangeAttr(Gf.Vec2f(0.1, 100))
    xf = UsdGeom.Xformable(cam)
    move = xf.AddTranslateOp()
    move.Set(Gf.Vec3d(-1.0, 1.2, 5.0), 0)
    move.Set(Gf.Vec3d(1.0, 1.2, 5.0), 48)
    xf.AddRotateXYZOp().Set(Gf.Vec3f(-10, 0, 0))
    stage.GetRootLayer().Save()


def write_arm(folder: Path) -> None:
    import trimesh

    (folder / "meshes").mkdir(parents=True, exist_ok=True)
    (folder / "arm.urdf").write_text(ARM)
    trimesh.creation.icosphere(subdivisions=2, radius=0.08).export(folder / "meshes" /
                                                                   "hand.stl")


if __name__ == "__main__":
    write_stage(HERE / "usd")
    write_arm(HERE / "arm")
