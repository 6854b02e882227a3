#!/usr/bin/env bash
# The packages as a user gets them after `make`: openmmdpd and openmmdpd_studies imported from a folder
# outside the clone, and the README's first Python example run there as a script.
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
for package in openmmdpd openmmdpd_studies; do
    "$PYTHON" -c "import $package; assert not $package.__file__.startswith('$repository/'), $package.__file__; print('import $package:', $package.__file__)"
done
echo "README example, run from $outside:"
"$PYTHON" readme_example.py
