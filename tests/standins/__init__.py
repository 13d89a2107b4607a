"""Test doubles of what cannot run on this machine, each at the outermost edge (a program on
PATH), named as a stand-in and following the real program's documented rules."""
