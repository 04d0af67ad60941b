# The baked sky visibility in the artist's materials: the shader node group "pleat sky visibility" and the
# operators that put it to use.
#
# The group reads the attributes the playback writes (playback.py) and gives, for the side of the surface the
# ray sees (Geometry ▸ Backfacing: the back where a back face is seen):
#   Sky Visibility  A of that side, in [0, 1] (1: open sky, 0: closed in)
#   Occlusion       1 - Strength x (1 - A): a factor ready to multiply into Base Color or to feed an ambient
#                   occlusion input (1 where nothing occludes, so multiplying by it changes nothing there)
# "Insert into materials" adds the group to every material of the object and multiplies Occlusion into each
# Principled BSDF's Base Color (whatever drove it before keeps driving it, through the multiply); nothing
# else of the material changes, and inserting again changes nothing. "Add material" gives an object with no
# material the template "pleat sky visibility": A of the side seen, as emission (judge it with the view
# transform Standard: Filmic lifts dark values).
#
# Blender 3.4 to 4.x: node group sockets are made with NodeTree.interface.new_socket from 4.0 on and
# NodeTree.inputs/outputs.new before; the Mix node (ShaderNodeMix, 3.4 on) is used for both floats and colours.

import bpy

from . import playback

GROUP = "pleat sky visibility"
MATERIAL = "pleat sky visibility"
INSERTED = "pleat occlusion"  # name of the multiply node inserted before a Base Color


def _new_socket(tree, name, in_out, default=None):
    """A float socket on the group's interface, in either API."""
    if hasattr(tree, "interface"):  # Blender 4.0 and later
        socket = tree.interface.new_socket(name, in_out=in_out, socket_type="NodeSocketFloat")
    else:
        sockets = tree.inputs if in_out == "INPUT" else tree.outputs
        socket = sockets.new("NodeSocketFloat", name)
    if default is not None:
        socket.default_value = default
        socket.min_value, socket.max_value = 0.0, 1.0
    return socket


def _socket(sockets, name, kind):
    """The socket named `name` of type `kind` ('VALUE', 'RGBA'): the Mix node has one per data type."""
    return next(s for s in sockets if s.name == name and s.type == kind)


def _mix(nodes, data_type, location):
    mix = nodes.new("ShaderNodeMix")
    mix.data_type, mix.location = data_type, location
    return mix


def node_group():
    """The shader node group "pleat sky visibility" (made once per file)."""
    tree = bpy.data.node_groups.get(GROUP)
    if tree is not None:
        return tree
    tree = bpy.data.node_groups.new(GROUP, "ShaderNodeTree")
    _new_socket(tree, "Strength", "INPUT", default=1.0)
    _new_socket(tree, "Occlusion", "OUTPUT")
    _new_socket(tree, "Sky Visibility", "OUTPUT")
    nodes, links = tree.nodes, tree.links
    group_in = nodes.new("NodeGroupInput")
    group_in.location = (-800, -200)
    group_out = nodes.new("NodeGroupOutput")
    group_out.location = (200, 0)
    geometry = nodes.new("ShaderNodeNewGeometry")
    geometry.location = (-800, 300)
    front = nodes.new("ShaderNodeAttribute")
    front.attribute_name, front.location = playback.FRONT, (-800, 100)
    back = nodes.new("ShaderNodeAttribute")
    back.attribute_name, back.location = playback.BACK, (-800, -50)
    side = _mix(nodes, "FLOAT", (-500, 150))  # the side seen: back where the ray meets a back face
    links.new(geometry.outputs["Backfacing"], _socket(side.inputs, "Factor", "VALUE"))
    links.new(front.outputs["Fac"], _socket(side.inputs, "A", "VALUE"))
    links.new(back.outputs["Fac"], _socket(side.inputs, "B", "VALUE"))
    sky = _socket(side.outputs, "Result", "VALUE")
    occlusion = _mix(nodes, "FLOAT", (-200, 0))  # 1 - strength (1 - A)
    links.new(group_in.outputs["Strength"], _socket(occlusion.inputs, "Factor", "VALUE"))
    _socket(occlusion.inputs, "A", "VALUE").default_value = 1.0
    links.new(sky, _socket(occlusion.inputs, "B", "VALUE"))
    links.new(_socket(occlusion.outputs, "Result", "VALUE"), group_out.inputs["Occlusion"])
    links.new(sky, group_out.inputs["Sky Visibility"])
    return tree


def material_template():
    """The material "pleat sky visibility" (made once): A of the side seen, as emission."""
    material = bpy.data.materials.get(MATERIAL)
    if material is not None:
        return material
    material = bpy.data.materials.new(MATERIAL)
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    group = nodes.new("ShaderNodeGroup")
    group.node_tree, group.location = node_group(), (-400, 0)
    emission = nodes.new("ShaderNodeEmission")
    emission.location = (-150, 0)
    links.new(group.outputs["Sky Visibility"], emission.inputs["Color"])
    output = nodes.new("ShaderNodeOutputMaterial")
    output.location = (50, 0)
    links.new(emission.outputs["Emission"], output.inputs["Surface"])
    return material


def insert_into_material(material):
    """Multiplies the group's Occlusion into the Base Color of each Principled BSDF of `material`. Returns the
    number of BSDFs changed (0 where it is already in, or where there is no Principled BSDF)."""
    if not material.use_nodes or material.node_tree is None:
        return 0
    nodes, links = material.node_tree.nodes, material.node_tree.links
    changed = 0
    for bsdf in [n for n in nodes if n.type == "BSDF_PRINCIPLED"]:
        base = bsdf.inputs["Base Color"]
        if base.is_linked and base.links[0].from_node.name.startswith(INSERTED):
            continue
        group = nodes.new("ShaderNodeGroup")
        group.node_tree = node_group()
        group.location = (bsdf.location.x - 450, bsdf.location.y - 250)
        multiply = _mix(nodes, "RGBA", (bsdf.location.x - 220, bsdf.location.y - 50))
        multiply.name = multiply.label = INSERTED
        multiply.blend_type = "MULTIPLY"
        _socket(multiply.inputs, "Factor", "VALUE").default_value = 1.0
        colour = _socket(multiply.inputs, "A", "RGBA")
        if base.is_linked:
            links.new(base.links[0].from_socket, colour)
        else:
            colour.default_value = base.default_value
        links.new(group.outputs["Occlusion"], _socket(multiply.inputs, "B", "RGBA"))
        links.new(_socket(multiply.outputs, "Result", "RGBA"), base)
        changed += 1
    return changed


class _OnActiveMesh:
    """What both operators share: they act on the active object, a mesh, and can be undone."""
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"


class PLEAT_OT_insert(_OnActiveMesh, bpy.types.Operator):
    """Multiply the baked sky visibility's occlusion into the Base Color of the object's materials (node
    group "pleat sky visibility"), keeping everything else of them"""
    bl_idname = "pleat.insert_node_group"
    bl_label = "Insert into materials"

    def execute(self, context):
        obj = context.active_object
        materials = [m for m in obj.data.materials if m is not None]
        if not materials:
            self.report({"ERROR"}, f"{obj.name} has no material: add one, or use Add material")
            return {"CANCELLED"}
        changed = sum(insert_into_material(m) for m in materials)
        without = [m.name for m in materials
                   if not any(n.type == "BSDF_PRINCIPLED" for n in (m.node_tree.nodes if m.node_tree else []))]
        note = f"; no Principled BSDF in {', '.join(without)}" if without else ""
        self.report({"INFO"}, f"pleat: occlusion multiplied into {changed} Base Color input(s){note}")
        return {"FINISHED"}


class PLEAT_OT_material(_OnActiveMesh, bpy.types.Operator):
    """Add the material template that shows the baked sky visibility (front or back by the side seen)"""
    bl_idname = "pleat.add_material"
    bl_label = "Add sky visibility material"

    def execute(self, context):
        obj = context.active_object
        material = material_template()
        if material.name not in obj.data.materials:
            obj.data.materials.append(material)
        if context.scene.view_settings.view_transform != "Standard":
            self.report({"INFO"}, "pleat: the template shows A as emission; Render ▸ Color Management ▸ View "
                                  "Transform Standard shows it unchanged")
        return {"FINISHED"}
