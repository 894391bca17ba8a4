#!/usr/bin/env bash
# Fetch MathJax from the npm registry at build time and install it for the offline docs site.
#
#   bash scripts/fetch_mathjax.sh docs/javascripts/mathjax/tex-svg.js
#
# Installs package/es5/tex-svg.js of mathjax@3.2.2 (the combined TeX-input / SVG-output
# component: self-contained, no web fonts) at OUTPATH, after checking its sha256 against the
# constant below; a mismatch is a hard error. Next to it goes input/tex/extensions/ from the same
# (npm-integrity-checked, sha256-pinned) tarball, so that TeX macros served by MathJax's
# autoload (\boldsymbol, \cancel, \color, mathtools, ...) load from the site instead of failing.
# Every file lands atomically (temporary file in the target directory, then mv); OUTPATH itself
# is written last, so its presence means a complete install. Nothing is committed: the target
# directory is gitignored.
set -euo pipefail

MATHJAX_VERSION="3.2.2"
# sha256 of the npm tarball mathjax-3.2.2.tgz and of its package/es5/tex-svg.js.
TARBALL_SHA256="1b9c0a1c44df864e915690558e72adb9cc5203360daefd385084ced3b6c64c09"
TEX_SVG_SHA256="d4295dc33744836935c1399feece5159577b34c5c8ffb9f1c6324cd82e03a882"

die() {
  echo "fetch_mathjax.sh: error: $*" >&2
  exit 1
}

[ $# -eq 1 ] || die "usage: $0 OUTPATH   (e.g. docs/javascripts/mathjax/tex-svg.js)"
out="$1"
outdir="$(dirname -- "$out")"
command -v npm >/dev/null 2>&1 || die "npm not found (apt-get install npm)"
command -v sha256sum >/dev/null 2>&1 || die "sha256sum not found"

work="$(mktemp -d "${TMPDIR:-/tmp}/fetch-mathjax.XXXXXX")"
trap 'rm -rf -- "$work"' EXIT

# A private npm cache: no dependence on (or pollution of) the user's ~/.npm.
echo "fetch_mathjax.sh: npm pack mathjax@${MATHJAX_VERSION}" >&2
(cd "$work" && npm pack "mathjax@${MATHJAX_VERSION}" --cache "$work/npm-cache" \
  --silent --no-audit --no-fund >"$work/pack.out") || die "npm pack mathjax@${MATHJAX_VERSION} failed"
tgz="$work/mathjax-${MATHJAX_VERSION}.tgz"
[ -f "$tgz" ] || die "npm pack did not produce $(basename -- "$tgz") (got: $(cat "$work/pack.out"))"

check_sha256() {  # FILE EXPECTED WHAT
  local got
  got="$(sha256sum -- "$1" | cut -d' ' -f1)"
  if [ "$got" != "$2" ]; then
    echo "fetch_mathjax.sh: error: sha256 mismatch for $3" >&2
    echo "  expected $2" >&2
    echo "  got      $got" >&2
    exit 1
  fi
}
check_sha256 "$tgz" "$TARBALL_SHA256" "mathjax-${MATHJAX_VERSION}.tgz"

tar -xzf "$tgz" -C "$work" package/es5/tex-svg.js package/es5/input/tex/extensions \
  || die "tarball lacks package/es5/tex-svg.js or package/es5/input/tex/extensions"
check_sha256 "$work/package/es5/tex-svg.js" "$TEX_SVG_SHA256" "package/es5/tex-svg.js"

install_atomic() {  # SRC DEST
  local dest_dir tmp
  dest_dir="$(dirname -- "$2")"
  mkdir -p -- "$dest_dir"
  tmp="$(mktemp "$dest_dir/.$(basename -- "$2").XXXXXX")"
  cp -- "$1" "$tmp"
  chmod 0644 -- "$tmp"
  mv -f -- "$tmp" "$2"
}

src_ext="$work/package/es5/input/tex/extensions"
n=0
while IFS= read -r -d '' f; do
  install_atomic "$f" "$outdir/input/tex/extensions/${f#"$src_ext"/}"
  n=$((n + 1))
done < <(find "$src_ext" -type f -name '*.js' -print0)
install_atomic "$work/package/es5/tex-svg.js" "$out"
echo "fetch_mathjax.sh: installed MathJax ${MATHJAX_VERSION} tex-svg.js (sha256 ${TEX_SVG_SHA256:0:12}…)" \
  "and $n TeX extensions under $outdir" >&2
