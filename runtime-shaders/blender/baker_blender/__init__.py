"""baker for Blender: brings every BAKER_* glTF extension (and EXT_mesh_primitive_edge_visibility) into Blender on
import and writes them back on export, through glTF-Blender-IO's user-extension hooks.

Install: Edit > Preferences > Add-ons > Install from Disk, pick the zip of this folder (``baker_blender.zip``).
Headless: put the folder that holds ``baker_blender`` on ``sys.path``, then ``import baker_blender;
baker_blender.enable()``.
"""
from __future__ import annotations

bl_info = {
    "name": "baker glTF extensions",
    "author": "baker",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "File > Import/Export > glTF 2.0",
    "description": "Keep BAKER_* glTF extensions through import and export; show the baked data in Blender",
    "category": "Import-Export",
}


class glTF2ImportUserExtension:
    """Called by Blender's glTF importer (it looks the class up on every enabled add-on's module)."""

    def gather_import_mesh_before_hook(self, pymesh, gltf):
        from . import widths
        widths.one_width(gltf, pymesh)  # baker's native layout mixes widths, which the stock importer cannot

    def gather_import_scene_after_nodes_hook(self, gltf_scene, blender_scene, gltf):
        from . import importing
        importing.after_import(gltf)


class glTF2ExportUserExtension:
    """Called by Blender's glTF exporter: custom attributes on, then the extensions go back into the written file."""

    def pre_export_hook(self, export_settings):
        export_settings["gltf_attributes"] = True  # the `_NAME` attributes follow the edited mesh

    def post_export_hook(self, export_settings):
        from . import exporting
        exporting.after_export(export_settings["gltf_filepath"])


def register():
    pass


def unregister():
    pass


def enable() -> None:
    """Enable the add-on in the running bpy session (headless use), so the glTF importer/exporter call its hooks."""
    import addon_utils
    import bpy

    if __name__ not in bpy.context.preferences.addons:
        addon_utils.enable(__name__, default_set=True, persistent=True)
    if __name__ not in bpy.context.preferences.addons:
        raise RuntimeError(f"{__name__} could not be enabled in this Blender session")
