#!/usr/bin/env bash
# The package as a user gets it after `make`: imported from a folder outside the clone, with the
# README's first Python example run there as a script.
set -euo pipefail
cd "$(dirname "$0")/.."
repository=$(pwd)
PYTHON=${PYTHON:-python3}
outside=$(mktemp -d)
trap 'rm -rf "$outside"' EXIT
"$PYTHON" - README.md "$outside/readme_example.py" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
example = re.search(r"```python\n(.*?)```", text, re.S).group(1)
open(sys.argv[2], "w").write(example)
PY
cd "$outside"
"$PYTHON" -c "import openmmdpd, os; assert not openmmdpd.__file__.startswith('$repository/'), openmmdpd.__file__; print('import openmmdpd:', openmmdpd.__file__)"
echo "README example, run from $outside:"
"$PYTHON" readme_example.py
