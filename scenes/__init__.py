"""The scenes: each one short unit, its numbers (with units), its mesh, its terms, its builder.

    scene.py    what every scene is (`Scene`); the parts only some have: the hand, static friction
    square.py   the lecture's case study: the mass-spring square dropped on a slope (`DEFAULTS`)
    chalk.py    the lecture's closing remark: Rabinowicz's chalk on a board, in a hand (`CHALK`)

`simulator.py` gathers them (`simulator.build_scene`, `simulator.build_chalk_scene`) and steps them.
"""
