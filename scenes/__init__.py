"""The scenes: each one short unit, its numbers (with units), its mesh, its terms, its builder, its
checks and the closed forms only it uses.

    scene.py        what every scene is (`Scene`, built by `assemble`); the parts only some have:
                    the hand, static friction, the moving surface; the contact (`HalfSpace`)
    square.py       the lecture's case study: the mass-spring square dropped on a slope (`DEFAULTS`)
    chalk.py        the lecture's closing remark: Rabinowicz's chalk on a board, in a hand (`CHALK`)
    tablecloth.py   the slide "Tangential Relative Velocity": a dish on a pulled tablecloth
                    (`TABLECLOTH`)
    grasp.py        the slide "Remarks - Applications": a block lifted between two pressed fingers
                    (`GRASP`)

`simulator.py` gathers the first three (`simulator.build_scene`, `build_chalk_scene`,
`build_tablecloth_scene`) and steps every scene; UNITS holds the units that declare their command
line and log columns themselves.
"""
from scenes import grasp

UNITS = {"grasp": grasp}    # the scenes that declare their command line and log columns as data:
#   FLAGS, LABEL, HELP, DURATION, PARAMS, BUILD (viewer/command/cli.py), HEADER (command/run.py),
#   TITLE (the page's: viewer/pictures/run_pictures.py),
#   LOG_COLUMNS (analysis/log.py)
