"""docs/settings.md, generated from gpu/settings.py: every setting's Blender property,
flag, type, range, default, preset values and meaning, expert ones marked. The page is
made here, not written by hand, so it cannot drift from the settings
(tests/rules/test_docs.py compares it with what this module makes).

    .venv/bin/python -m lpv_preview.cli.settings_page docs/settings.md
"""
import sys
import textwrap
from dataclasses import MISSING

from ..gpu.settings import (COMMAND_LINE_ONLY, COMPARISON_PARAMETERS, CORRECTION_PARAMETERS, DISPLAY_PARAMETERS,
                            INDIRECT_METHOD_ONLY, PARAMETERS, PRESETS)

COMMAND = ".venv/bin/python -m lpv_preview.cli.settings_page docs/settings.md"
"""The command that writes the page again."""

RENDERING_COMMANDS = "demo, render, compare, bench"
"""The commands that take every pipeline setting as a flag (cli/flags.py add_setting_flags)."""

FLAGS = {
    "debug_passes": "`--debug-passes` (demo, render)",
    "compare_samples": "`compare --samples`",
    "compare_noise_floor": "`compare --no-noise-floor` turns it off",
    "compare_peers": "`compare --no-peers` turns it off",
    "correct_seconds": "`--correct-seconds` (demo, render)",
    "correction_workers": "`--workers` (demo, render)",
}
"""The flags of settings outside the pipeline's (cli/parser.py, cli/flags.py); a setting
of the comparison's methods is a name in a list flag, one not here has no flag."""

FROM_BLENDER = {"width": "the render resolution", "height": "the render resolution"}
"""Settings Blender supplies rather than a property of the panel (addon/ui.py FROM_BLENDER)."""

SECTIONS = (
    ("Pipeline", PARAMETERS,
     f"What a frame is rendered with. Each is a flag of `{RENDERING_COMMANDS}` and a property in the panels; "
     "`--preset` (or a preset button) sets the ones its column names and leaves the rest."),
    ("Viewport, overlays and debug passes", DISPLAY_PARAMETERS,
     "What the viewport shows and how long a still viewport converges; they rerun no stage of the frame."),
    ("Compare with Cycles", COMPARISON_PARAMETERS,
     "What Compare with Cycles (Render properties) and `compare` render."),
    ("Corrections toward Cycles", CORRECTION_PARAMETERS,
     "How long a render is corrected toward Cycles, and by how many sample workers."),
)


def blender_name(name):
    """The property's label in the panels (addon/properties.py)."""
    if name in COMMAND_LINE_ONLY:
        return "— (command line only)"
    if name in FROM_BLENDER:
        return f"— ({FROM_BLENDER[name]})"
    return name.replace("_", " ").capitalize()


def flag_of(name):
    if name in PARAMETERS:
        flag = name.replace("_", "-")
        return f"`--{flag}`, `--no-{flag}`" if type_of(PARAMETERS[name]) == "bool" else f"`--{flag}`"
    if name.startswith("compare_") and name not in FLAGS:
        method = name.removeprefix("compare_")
        list_flag = "--indirect-methods" if method in ("lpv", "light_grid", "vpl_gather") else "--methods"
        return f"`compare {list_flag}` lists `{method}`"
    return FLAGS.get(name, "— (Blender only)")


def type_of(field):
    if field.metadata["choices"] is not None:
        return "choice"
    return field.type if isinstance(field.type, str) else field.type.__name__


def range_of(field):
    meta = field.metadata
    if meta["choices"] is not None:
        return ", ".join(f"`{choice}`" for choice in meta["choices"])
    if meta["min"] is None:
        return "on / off"
    return f"{meta['min']} – {meta['max']}"


def value_text(value):
    if isinstance(value, bool):
        return "on" if value else "off"
    return f"`{value}`" if isinstance(value, str) else f"{value:,}" if isinstance(value, int) else f"{value:g}"


def default_of(name, field):
    default = value_text(field.default) if field.default is not MISSING else ""
    if name in FROM_BLENDER:
        return f"{default} (`demo`, `render`, `compare`: the scene's)"
    return default


def presets_of(name):
    values = [(preset, values[name]) for preset, values in PRESETS.items() if name in values]
    return ", ".join(f"{preset} {value_text(value)}" for preset, value in values)


def description_of(name, field):
    text = field.metadata["description"].rstrip(".") + "."
    if name in INDIRECT_METHOD_ONLY:
        text += f" Read by the indirect method `{INDIRECT_METHOD_ONLY[name]}` only."
    return text.replace("|", "\\|")


def section_table(parameters):
    lines = ["| setting | flag | type | range | default | presets | what it does |", "|---|---|---|---|---|---|---|"]
    for name, field in parameters.items():
        setting = f"`{name}`" + (" **expert**" if field.metadata["expert"] else "")
        cells = (f"{setting}<br>{blender_name(name)}", flag_of(name), type_of(field), range_of(field),
                 default_of(name, field), presets_of(name), description_of(name, field))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def settings_page():
    """The Markdown of docs/settings.md."""
    experts = [name for parameters in (PARAMETERS, DISPLAY_PARAMETERS, COMPARISON_PARAMETERS, CORRECTION_PARAMETERS)
               for name, field in parameters.items() if field.metadata["expert"]]
    parts = [
        "# Settings\n",
        "<!-- Generated from gpu/settings.py; do not edit. Write it again with:\n"
        f"     {COMMAND} -->\n",
        "Every setting of LPV Preview, from `gpu/settings.py`, the one place each is defined. In Blender each "
        "is a property of the scene (`scene.lpv_preview`), shown in the Render properties when LPV Preview is "
        "the render engine and in the 3D view's sidebar tab \"LPV Preview\", under the label in the first "
        "column. On the command line the pipeline's settings are flags of every command that renders; "
        "each command's `--help` lists them with their ranges.\n",
        f"Settings marked **expert** ({len(experts)} of them) are internals of a stage or switches for tests "
        "and references: the defaults suit every scene, and the presets never change them. Change one to "
        "study the method (docs/method.md), not to make a picture better.\n",
        "Presets (`--preset`, the buttons at the top of the panel) set the values their column gives; the "
        "flags given, or the properties changed afterwards, override them. A setting only one indirect method "
        "reads says which.\n",
    ]
    for title, parameters, text in SECTIONS:
        parts += [f"## {title}\n", text + "\n", section_table(parameters)]
    return "\n".join(part if part.startswith(("|", "<!--")) else textwrap.fill(part, 100, break_on_hyphens=False) + "\n" for part in parts)


def write_settings_page(path):
    with open(path, "w") as handle:
        handle.write(settings_page())


if __name__ == "__main__":
    write_settings_page(sys.argv[1] if len(sys.argv) > 1 else "docs/settings.md")
