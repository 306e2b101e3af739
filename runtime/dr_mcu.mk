# dr_mcu.mk - the avr-gcc options of every MCU build of dynarole, in one place: the generated
# Makefile (which gets a copy), runtime/avr's firmware, runtime/nesc's AVR build and
# scripts/bench-avr include or read this line.
#
# Flash, each option measured on eight2car (docs/benchmarks.md, "Code-generation options"):
# -Os; -mcall-prologues (one shared register save and restore); -mstrict-X (fewer pointer
# copies); -flto -ffat-lto-objects (objects usable both ways: an image linked with -flto has
# the runtime, the program and the platform optimised as one unit, small functions inlined
# across files and unused ones dropped); -mrelax (short calls and jumps where they reach);
# -fno-tree-loop-optimize -fno-gcse -fno-move-loop-invariants (no loop rewriting, global
# common subexpressions or hoisting: on an 8-bit core with few free registers these add
# more spills and copies than they save).
DR_MCU_FLAGS = -Os -mcall-prologues -mstrict-X -flto -ffat-lto-objects -mrelax -fno-tree-loop-optimize -fno-gcse -fno-move-loop-invariants
