"""Build the extension zip that Blender installs: `python scripts/build_extension.py [--out dist]`.

The wheels to bundle are the ones blender_manifest.toml lists; each missing one is
downloaded from PyPI into ./wheels by its exact file name (package, version, Python and
platform tags read from the name), and one it no longer lists is removed from there
(Blender's builder packs the whole folder); then Blender's own builder (bl_pkg's blender_ext.py,
inside the bpy package) validates the manifest and writes the zip. Prints the zip's path.
"""
import argparse
import os
import subprocess
import sys
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def blender_ext_script():
    import bpy
    return os.path.join(bpy.utils.system_resource("SCRIPTS"), "addons_core", "bl_pkg", "cli", "blender_ext.py")


def download_wheel(path):
    """pip download the exact wheel file `path` (its name says what and for where)."""
    name, version, python, abi, platforms = os.path.basename(path)[:-len(".whl")].split("-")
    platform_flags = [flag for tag in platforms.split(".") for flag in ("--platform", tag)]
    subprocess.run([sys.executable, "-m", "pip", "download", "--quiet", "--no-deps", "--only-binary=:all:",
                    f"{name}=={version}", "--python-version", python[2:3] + "." + python[3:],
                    "--implementation", python[:2], "--abi", abi, *platform_flags,
                    "--dest", os.path.dirname(path)], check=True)
    if not os.path.isfile(path):
        raise SystemExit(f"pip did not produce {os.path.basename(path)}; check the name in blender_manifest.toml.")


def build(out_dir):
    with open(os.path.join(ROOT, "blender_manifest.toml"), "rb") as handle:
        manifest = tomllib.load(handle)
    listed = {os.path.normpath(os.path.join(ROOT, wheel)) for wheel in manifest.get("wheels", [])}
    for path in listed:
        if not os.path.isfile(path):
            os.makedirs(os.path.dirname(path), exist_ok=True)
            download_wheel(path)
    for folder in {os.path.dirname(path) for path in listed}:  # the builder packs the whole folder
        for name in os.listdir(folder):
            if name.endswith(".whl") and os.path.join(folder, name) not in listed:
                os.remove(os.path.join(folder, name))  # a download the manifest no longer lists
    os.makedirs(out_dir, exist_ok=True)
    subprocess.run([sys.executable, blender_ext_script(), "build", "--source-dir", ROOT, "--output-dir", out_dir],
                   check=True, stdout=sys.stderr)
    return os.path.join(out_dir, f"{manifest['id']}-{manifest['version']}.zip")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(ROOT, "dist"), help="folder for the zip (default: dist)")
    args = parser.parse_args(argv)
    print(build(os.path.abspath(args.out)))


if __name__ == "__main__":
    main()
