#!/usr/bin/python3
"""Identifiers some GLSL compilers refuse, in every shader file the backends embed.

glslang accepts a variable named `packed`; NVIDIA's compiler does not (`const uint packed = ...` is a syntax error
there): the GLSL 4.50 and GLSL ES 3.20 specs reserve some words for future use, and their layout-qualifier
identifiers are keywords to compilers that parse `layout(...)` with a fixed grammar. This lint reads each file in
shaders/ with comments removed and fails on any of those words used outside a `layout(...)` list. Every GL and
Vulkan variant is one file's text with some #if branches dropped, so checking the whole file checks them all.

Usage: shader_lint.py SHADER_DIR   (exit 1 on a finding; --self-test shows it fails on planted uses)
"""
import pathlib
import re
import sys

# GLSL 4.50 section 3.6 and GLSL ES 3.20 section 3.7: keywords reserved for future use.
RESERVED = """common partition active asm class union enum typedef template this resource goto inline noinline public
static extern external interface long short half fixed unsigned superp input output hvec2 hvec3 hvec4 fvec2 fvec3
fvec4 sampler3DRect filter sizeof cast namespace using""".split()
# GLSL 4.50 section 4.4 and GLSL ES 3.20 section 4.4: layout-qualifier identifiers (plus the block layouts).
LAYOUT_QUALIFIERS = """shared packed std140 std430 row_major column_major location component binding offset index
align xfb_buffer xfb_offset xfb_stride origin_upper_left pixel_center_integer early_fragment_tests triangles quads
isolines equal_spacing fractional_even_spacing fractional_odd_spacing cw ccw point_mode points lines lines_adjacency
triangles_adjacency invocations line_strip triangle_strip max_vertices stream vertices local_size_x local_size_y
local_size_z depth_any depth_greater depth_less depth_unchanged blend_support_all_equations""".split()
FORBIDDEN = set(RESERVED) | set(LAYOUT_QUALIFIERS)
# Words a shader may still write as a qualifier or statement outside layout(): `shared` in compute and task stages.
QUALIFIER_USES = {"shared": re.compile(r"^\s*shared\s+\w")}


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def without_layouts(line):
    """The line with every layout(...) list blanked (nested parentheses included)."""
    out, i = [], 0
    for m in re.finditer(r"\blayout\s*\(", line):
        if m.start() < i:
            continue
        out.append(line[i:m.start()])
        depth, j = 1, m.end()
        while j < len(line) and depth:
            depth += {"(": 1, ")": -1}.get(line[j], 0)
            j += 1
        i = j
    out.append(line[i:])
    return " ".join(out)


def findings(name, text):
    found = []
    for number, line in enumerate(strip_comments(text).splitlines(), 1):
        if line.lstrip().startswith("#"):  # preprocessor lines: #extension names, #define names of our own
            continue
        for word in re.findall(r"\b[A-Za-z_]\w*\b", without_layouts(line)):
            if word in FORBIDDEN and not (word in QUALIFIER_USES and QUALIFIER_USES[word].match(line)):
                found.append(f"{name}:{number}: '{word}' is reserved or a layout qualifier in GLSL 4.50 / ES 3.20 "
                             f"(NVIDIA's compiler rejects it as a name): {line.strip()}")
    return found


def self_test():
    planted = {
        "const uint packed = 1u;": True,
        "vec3 filter = vec3(0.0);": True,
        "float input;": True,
        "int index = 0;": True,
        "layout(std430, binding = 4) readonly buffer B { uint x[]; };": False,
        "shared uint face_masks[32];": False,
        "// packed in a comment": False,
        "uint packed_corners = 0u;": False,
    }
    wrong = [s for s, bad in planted.items() if bool(findings("planted", s)) != bad]
    for s in wrong:
        print(f"self-test: lint got '{s}' wrong")
    return not wrong


def main():
    if not self_test():
        return 1
    shader_dir = pathlib.Path(sys.argv[1])
    files = sorted(p for p in shader_dir.iterdir() if p.is_file())
    found = [f for p in files for f in findings(p.name, p.read_text())]
    for f in found:
        print(f)
    print(f"{len(files)} shader files linted, {len(found)} finding(s); self-test: planted names caught")
    return 1 if found or not files else 0


if __name__ == "__main__":
    sys.exit(main())
