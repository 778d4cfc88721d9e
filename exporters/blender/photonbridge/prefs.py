"""Add-on preferences: where the photonbridge binary is (then
$PHOTONBRIDGE_BIN, then PATH; cli.find_binary)."""
import bpy
from bpy.props import StringProperty


class PhotonbridgePreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    binary: StringProperty(
        name="Binary", subtype='FILE_PATH',
        description="The photonbridge executable (e.g. build/photonbridge of the checkout); empty: "
        "$PHOTONBRIDGE_BIN, then PATH")

    def draw(self, context):
        self.layout.prop(self, "binary")


classes = (PhotonbridgePreferences,)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
