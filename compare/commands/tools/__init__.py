"""Developer tools: surveys, tables and benchmarks of the harness and its simulators.

    python -m compare tools TOOL [...]        python -m compare tools TOOL --help

The surveys run a check over every scene and integrator (the CI runs step-survey and mutation on
every change); the tables print the Markdown tables the docs show; the benchmarks time one thing
in one run. docs/cli.md describes each.
"""

METAVAR = "TOOL"
SUBCOMMANDS = {   # python -m compare tools TOOL: name -> its command module, in the order --help lists them
    "step-survey": "compare.commands.tools.step_survey",
    "dynamics-survey": "compare.commands.tools.dynamics_survey",
    "mutation": "compare.commands.tools.mutation",
    "stability-table": "compare.commands.tools.stability_table",
    "energy-table": "compare.commands.tools.energy_table",
    "mapping-table": "compare.commands.tools.mapping_table",
    "overhead": "compare.commands.tools.overhead",
    "chatter-cost": "compare.commands.tools.chatter_cost",
    "twin-speed": "compare.commands.tools.twin_speed",
    "identify-bench": "compare.commands.tools.identify_bench",
    "study-bench": "compare.commands.tools.study_bench",
    "game-demo": "compare.commands.tools.game_demo",
    "game-fps": "compare.commands.tools.game_fps",
}
