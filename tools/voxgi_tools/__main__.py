"""python -m voxgi_tools COMMAND [ARGS]: voxgi's benchmarks and tools.

Each command is what one wrapper in tools/ runs (`tools/bench-convergence ARGS` is
`python -m voxgi_tools bench convergence ARGS`); `COMMAND --help` tells more.
"""
import importlib
import sys

# command -> (module, wrapper in tools/, one line)
COMMANDS = {
    "sweep": ("sweep", "sweep", "what accuracy costs in time: a grid of settings"),
    "samples": ("samples_sheet", "samples-sheet", "a contact sheet of the glTF samples"),
    "flip": ("metrics", "flip", "FLIP of an image against a reference"),
    "reference": ("reference", "make-reference", "path-traced references of the set's views"),
    "make-hall": ("make_hall", "make-hall", "write the validation set's hall scenes"),
    "mitsuba": ("mitsuba_scene", None, "render a scene with Mitsuba 3 (the races' anchor)"),
    "validation-set": ("validation_set", None, "the set's views: a view's scene and flags"),
}
BENCHES = {
    "budget": "the frame budget: held target, the work mask against uniform",
    "convergence": "rtgi against the path tracer and Mitsuba as time goes by",
    "motion": "rtgi's error at the end of a camera move",
    "pathtrace": "path tracer throughput per device, against Mitsuba",
    "regression": "the headline accuracy figures against the committed ones",
    "rtgi": "rtgi's frame and stages by size, bounces, grid and interleave",
    "scale": "start-up, memory and frame time against triangle count",
    "screen": "the viewer's frames under its frame budget",
    "terms": "each term's error against the path tracer's depth-limited image",
}


def usage(out):
    print(__doc__, file=out)
    print("commands:", file=out)
    for name, (_, _, what) in COMMANDS.items():
        print(f"  {name:22s}{what}", file=out)
    for name, what in BENCHES.items():
        print(f"  bench {name:16s}{what}", file=out)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        usage(sys.stdout if argv else sys.stderr)
        return 0 if argv else 2
    if argv[0] == "bench":
        if len(argv) < 2 or argv[1] not in BENCHES:
            print(f"voxgi_tools bench: expected one of {', '.join(BENCHES)}", file=sys.stderr)
            return 2
        module, prog, rest = f"bench_{argv[1]}", f"bench-{argv[1]}", argv[2:]
    elif argv[0] in COMMANDS:
        module, prog, _ = COMMANDS[argv[0]]
        prog, rest = prog or argv[0], argv[1:]
    else:
        print(f"voxgi_tools: no command '{argv[0]}' (--help lists them)", file=sys.stderr)
        return 2
    # Each module's argparse reads sys.argv and names itself after the wrapper.
    sys.argv = [f"tools/{prog}"] + rest
    return importlib.import_module(f"voxgi_tools.{module}").main(rest) or 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
