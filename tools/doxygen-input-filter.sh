#!/usr/bin/env bash
# Doxygen's INPUT_FILTER (docs/Doxyfile): prints the header $1 for Doxygen to read.  The headers' comments
# write run averages as <x> (k_B T_conf = <gradientSquared> / <laplacian>), which Doxygen would take for
# HTML tags and reject; in comment lines (those starting with /** or *) such a bracketed name is escaped
# to Doxygen's literal \< \>.  Code lines are left alone, so template arguments stay C++.
exec sed -E '/^[[:space:]]*(\/\*\*|\*)/ s/<([A-Za-z_][A-Za-z_0-9]*)>/\\<\1\\>/g' "$1"
