#!/usr/bin/env python3
"""Instructions per triangle in each stage of a frame, from a callgrind profile.

Takes: a callgrind output file made with --dump-instr=yes of `mosaic render ... --stats`, the
mosaic binary it profiled (built with -g), and the `--stats` JSON line of that run. Gives: a
markdown table of instructions per stage, per submitted triangle and per (triangle, tile) pair.

The front end, binning, tile and resolve stages are callgrind's inclusive costs of their
functions. Inside the tile kernel, whose stages are inlined into one function per draw state,
each instruction goes to the stage of the innermost named function in its inline chain
(addr2line -i): coverage, depth, colour, hierarchical z; the few-pixel path is one stage of its
own; what is left in the walkers is the walk (the box's blocks, the corner tests, the loop over
covered vectors)."""
import collections
import json
import re
import subprocess
import sys

# Stages of a frame: the inclusive cost of the function whose name matches (the largest, where
# callgrind lists it under several source files).
FRAME_STAGES = [
    ("frame (Renderer::render)", r"^mosaic::Renderer::render\("),
    ("vertex stage", r"FrontEndSimd<[^>]*>::project_vertices\("),
    ("front end (setup)", r"^mosaic::bin::set_up_chunk\("),
    ("binning", r"^mosaic::bin::bin_chunk\("),
    ("tiles (TileKernelImpl::run)", r"TileKernelImpl<[^>]*>::run\("),
    ("resolve (part of the tiles)", r"TileKernelImpl<[^>]*>::resolve_tile\("),
]

# Stages inside the tile kernel, by the functions of an instruction's inline chain. A chain
# through the few-pixel path is that path's; otherwise the innermost function that names a
# stage gives it, and a chain that names none is the walk.
PIXEL_PATH = re.compile(r"::(pixel_impl|few_pixels|pixel_samples)<")
KERNEL_STAGES = [
    ("coverage", re.compile(r"::(coverage32|coverage32_rows|coverage32_rows_of|coverage32_rows_any|"
                            r"coverage_f64|build_doff|vectors_with_lanes|lanes_of)(<[^()]*>)?\(")),
    ("depth", re.compile(r"::(DepthLanes::at|test_and_write_depth<|passes<|take_plane\(|record_plane\()")),
    ("colour", re.compile(r"::(write_color<|color_generic\()|ShadeSimd<")),
    ("hierarchical z", re.compile(
        r"(hiz_classify|BlockDepthRange|BlockDepthRows|keep_block_bounds|update_block_bounds|"
        r"exact_block_bounds|refresh_tile_z|HizSimd|store_hiz)")),
]
# Helpers that several stages call (the clamp of depth and colour alike): an instruction in one
# goes to the stage of the function that called it.
SHARED_HELPERS = re.compile(r"ShadeSimd<[^>]*>::clamp\(")
KERNEL_FUNCTIONS = re.compile(r"TileKernelImpl<|ShadeSimd<")
# The functions that draw triangles in a tile (not its clear or resolve), whose instructions the
# split above divides.
WALKERS = re.compile(r"::(triangle_impl<|depth_only_walker<|pixel_impl<|small_box<|take_plane\(|"
                     r"draw_run\(|draw_nearest_first\(|color_generic\()|ShadeSimd<")


def self_costs(path, pattern):
    """Self cost (Ir) per instruction address of every function matching `pattern`."""
    names, cost = {}, collections.Counter()
    selected, addr, after_calls = False, 0, False
    for line in open(path):
        if line.startswith(("fn=", "cfn=")):
            m = re.match(r"c?fn=\((\d+)\)(?: (.*))?", line.strip())
            if m.group(2):
                names[m.group(1)] = m.group(2)
            if line.startswith("fn="):
                selected = pattern.search(names.get(m.group(1), "")) is not None
            continue
        if line.startswith("calls="):
            after_calls = True  # the next cost line is the call's inclusive cost
            continue
        if not line or not (line[0].isdigit() or line[0] in "+-*"):
            continue
        parts = line.split()
        tok = parts[0]
        if tok == "*":
            pass
        elif tok[0] in "+-":
            addr += int(tok, 0)
        else:
            addr = int(tok, 0)
        if after_calls:
            after_calls = False
            continue
        if selected and len(parts) >= 3:
            cost[addr] += int(parts[2])
    return cost


def inline_chains(binary, addrs):
    """Function names of each address's inline chain, innermost first (addr2line -a -f -i -C)."""
    chains, cur, expect_name = {}, None, True
    out = subprocess.run(["addr2line", "-a", "-f", "-i", "-C", "-e", binary] +
                         ["%x" % a for a in addrs], capture_output=True, text=True, check=True)
    for line in out.stdout.splitlines():
        if line.startswith("0x"):
            cur = int(line, 16)
            chains[cur] = []
            expect_name = True
        elif expect_name:
            chains[cur].append(line)
            expect_name = False
        else:
            expect_name = True  # the file:line of the name above
    return chains


def kernel_stage(chain):
    if any(PIXEL_PATH.search(f) for f in chain):
        return "few-pixel path"
    for fn in chain:
        if SHARED_HELPERS.search(fn):
            continue
        for stage, pattern in KERNEL_STAGES:
            if pattern.search(fn):
                return stage
    return "walk"


def inclusive_costs(path):
    out = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", path],
                         capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines():
        m = re.match(r"\s*([\d,]+) \([\s\d.]+%\)\s+[^:\s]+:(.*?)(?: \[.*\])?$", line)
        if m:
            rows.append((int(m.group(1).replace(",", "")), m.group(2)))
    return rows


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: per_stage.py CALLGRIND_OUT MOSAIC_BINARY STATS_JSON_LINE")
    path, binary, stats_line = sys.argv[1:]
    stats = json.loads(stats_line)
    triangles, pairs = stats["triangles_in"], stats["triangles_binned"]
    if triangles == 0:
        sys.exit("per_stage.py: the frame has no triangles to divide by")
    incl = inclusive_costs(path)

    def inclusive(pattern):
        return max((c for c, fn in incl if re.search(pattern, fn)), default=0)

    print("| stage | instructions | per triangle | per (triangle, tile) pair |")
    print("|---|---:|---:|---:|")

    def row(name, n, pair=True):
        per_pair = "%.0f" % (n / pairs) if pair and pairs else "—"
        print("| %s | %d | %.0f | %s |" % (name, n, n / triangles, per_pair))

    stage_cost = {}
    for name, pattern in FRAME_STAGES:
        stage_cost[name] = inclusive(pattern)
        row(name, stage_cost[name], name.startswith(("tiles", "resolve")))
    costs = self_costs(path, KERNEL_FUNCTIONS)
    chains = inline_chains(binary, sorted(costs))
    split = collections.Counter()
    for addr, n in costs.items():
        chain = chains.get(addr, [])
        if any(WALKERS.search(f) for f in chain):
            split[kernel_stage(chain)] += n
    for stage in ["walk", "coverage", "depth", "colour", "hierarchical z", "few-pixel path"]:
        row("tiles: " + stage, split[stage])
    rest = stage_cost["tiles (TileKernelImpl::run)"] - sum(split.values())
    row("tiles: clear, resolve, shader and library calls", rest)


if __name__ == "__main__":
    main()
