# Blender add-on: bakes pleat's sky visibility onto the active object over the scene's frame range and plays
# it back on the artist's own mesh (README "In Blender"). Debian's Blender 3.4 with its system Python 3.11;
# the computation goes through the `pleat` Python module, which must be importable by that Python.
#
# The contract (tests/blender/bake_test.py checks it against `pleat visibility`):
# - Baking reads the active object's evaluated mesh (modifiers, caches) and the evaluated meshes of the chosen
#   collection's objects (occluders) at every frame of the scene's range, in world space. Quads and n-gons
#   are split into triangles once, as Blender splits them at the first frame (concave polygons inside their
#   outline), and that split is kept for every frame (bake.py): the vertices and polygons must stay the same
#   over the range, and the object's evaluated mesh must have its own mesh's vertices (in order), which get
#   the results.
# - The result goes to a cache file beside the .blend (cache.py), named on the object (custom property
#   `pleat_cache`); nothing is written when the bake fails or is cancelled.
# - At every frame change the object's mesh gets the frame's values (playback.py): float point attributes
#   `pleat_front` and `pleat_back` (A of each side, docs/method.md §1) and colour attributes
#   `pleat_sky_color`, `pleat_sky_color_back` (each side's A as grey). Outside the baked range the nearest
#   baked frame's values hold. The node group "pleat sky visibility" brings them into materials (shading.py);
#   results computed elsewhere (a CSV, a cone cache) load onto the object the same way (results.py).
#
# Blender 3.4 and later: 4.0's node group interface API is handled in shading.py; nothing here uses what 4.x
# removed (Mesh.calc_normals, use_auto_smooth, bgl, vertex_colors). The module pleat must be built for
# Blender's Python version. python/blender/install.py installs both.

bl_info = {
    "name": "pleat: bake sky visibility",
    "author": "pleat",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties ▸ Object ▸ pleat; 3D View ▸ Sidebar ▸ pleat",
    "description": "Bakes per-vertex sky visibility of folded cloth (front and back) with pleat",
    "category": "Animation",
}

import bpy

from . import bake, playback, results, shading


class PleatSettings(bpy.types.PropertyGroup):
    occluders: bpy.props.PointerProperty(
        type=bpy.types.Collection, name="Occluders",
        description="Objects that block the cloth's sky (bodies, colliders); evaluated every frame")
    engine: bpy.props.EnumProperty(
        name="Engine", default="kinetic",
        items=[("kinetic", "Kinetic", "Follow the cloth from frame to frame (faster on animation)"),
               ("static", "Static", "Compute every frame from scratch")])
    orientations: bpy.props.IntProperty(
        name="Orientations", default=0, min=0,
        description="Plane orientations of the slicing plan (0: pleat's default)")
    spacing: bpy.props.FloatProperty(
        name="Spacing", default=0.0, min=0.0, unit="LENGTH",
        description="Distance between parallel planes (0: pleat's default, half the average edge length)")
    paper: bpy.props.BoolProperty(
        name="Paper's plan", default=False,
        description="The paper's method: its 6 axis-aligned plane orientations and nearer-endpoint cone "
                    "storage (pleat visibility --paper; overrides Orientations)")
    plan: bpy.props.StringProperty(
        name="Plan file", subtype="FILE_PATH", default="",
        description="A plan saved by `pleat visibility --save-plan` (replaces the placement options)")
    ground: bpy.props.BoolProperty(
        name="Ground", default=False, description="An infinite ground plane z = height blocks the sky")
    ground_height: bpy.props.FloatProperty(name="Height", default=0.0, unit="LENGTH")
    contact_tolerance: bpy.props.FloatProperty(
        name="Contact tolerance", default=0.0, min=0.0, unit="LENGTH",
        description="How far behind an open occluder (a plane) the cloth still rests on it; cloth inside a closed "
                    "occluder or under the ground always does, and deeper vertices are reported "
                    "(0: pleat's default, half the cloth's mean edge length)")


class PLEAT_PT_panel:
    bl_label = "pleat sky visibility"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.pleat
        layout.prop(settings, "occluders")
        layout.prop(settings, "engine")
        column = layout.column(align=True)
        column.prop(settings, "plan")
        sub = column.column(align=True)
        sub.enabled = not settings.plan
        sub.prop(settings, "orientations")
        sub.prop(settings, "spacing")
        sub.prop(settings, "paper")
        row = layout.row(align=True)
        row.prop(settings, "ground")
        sub = row.row()
        sub.enabled = settings.ground
        sub.prop(settings, "ground_height")
        layout.prop(settings, "contact_tolerance")
        layout.operator(bake.PLEAT_OT_bake.bl_idname, icon="RENDER_ANIMATION")
        layout.operator(results.PLEAT_OT_load.bl_idname, icon="IMPORT")
        obj = context.active_object
        if obj is not None and playback.CACHE_PROPERTY in obj:
            layout.label(text="Baked: " + obj[playback.CACHE_PROPERTY], icon="CHECKMARK")
            row = layout.row(align=True)
            row.operator(shading.PLEAT_OT_insert.bl_idname, icon="NODETREE")
            row.operator(shading.PLEAT_OT_material.bl_idname, icon="MATERIAL")


class PLEAT_PT_object(PLEAT_PT_panel, bpy.types.Panel):
    bl_idname = "PLEAT_PT_object"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"


class PLEAT_PT_sidebar(PLEAT_PT_panel, bpy.types.Panel):
    bl_idname = "PLEAT_PT_sidebar"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "pleat"


classes = (PleatSettings, bake.PLEAT_OT_bake, results.PLEAT_OT_load, shading.PLEAT_OT_insert,
           shading.PLEAT_OT_material, PLEAT_PT_object, PLEAT_PT_sidebar)


def _numpy_bool_for_gltf_import():
    """Blender 3.4's glTF importer uses numpy.bool, which numpy 1.24 removed (Debian 12 has both): File ▸
    Import ▸ glTF fails with "module 'numpy' has no attribute 'bool'". The alias meant the builtin bool."""
    import numpy

    if bpy.app.version < (3, 6, 0) and "bool" not in numpy.__dict__:
        numpy.bool = bool


def register():
    _numpy_bool_for_gltf_import()
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.pleat = bpy.props.PointerProperty(type=PleatSettings)
    playback.register()


def unregister():
    playback.unregister()
    del bpy.types.Scene.pleat
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
