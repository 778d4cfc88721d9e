"""File > Export > photonbridge glTF: the render engine's own hand-off
(writer.py) as an operator, so the file photonbridge renders can be
inspected, validated and rendered by hand."""
import bpy
from bpy.props import StringProperty
from bpy_extras.io_utils import ExportHelper

from . import writer


class EXPORT_SCENE_OT_photonbridge_gltf(bpy.types.Operator, ExportHelper):
    """Write the evaluated scene as the glTF (and PHOTONBRIDGE_blender extension) the photonbridge render engine
    renders"""
    bl_idname = "export_scene.photonbridge_gltf"
    bl_label = "Export photonbridge glTF"
    filename_ext = ".gltf"
    filter_glob: StringProperty(default="*.gltf", options={'HIDDEN'})

    def execute(self, context):
        depsgraph = context.evaluated_depsgraph_get()
        report = writer.write_gltf(depsgraph, self.filepath)
        for w in report.warnings:
            self.report({'WARNING'}, w)
        for w in report.notes:
            self.report({'INFO'}, w)
        self.report({'INFO'}, "photonbridge glTF: %d triangles, %d meshes, %d instances, %d lights in %.2f s -> %s"
                    % (report.triangles, report.meshes, report.instances, report.lights, report.seconds,
                       self.filepath))
        return {'FINISHED'}


def menu_func(self, context):
    self.layout.operator(EXPORT_SCENE_OT_photonbridge_gltf.bl_idname, text="photonbridge glTF (.gltf)")


classes = (EXPORT_SCENE_OT_photonbridge_gltf,)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.TOPBAR_MT_file_export.append(menu_func)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(menu_func)
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
