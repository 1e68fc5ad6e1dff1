#!/usr/bin/env bash
# Regenerate docs/case-reference.md from the case reader's own key declarations.
set -euo pipefail
cd "$(dirname "$0")/.."
{
  cat docs/case-reference.head.md
  ./build/bin/efsi keys
} > docs/case-reference.md
echo "wrote docs/case-reference.md"
