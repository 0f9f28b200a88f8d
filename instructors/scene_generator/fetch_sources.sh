#!/usr/bin/env bash
# Downloads the pinned mesh sources listed in sources.txt, checks their
# SHA-256 sums and extracts the files the scene generator reads.
#
#   instructors/scene_generator/fetch_sources.sh [DIR]
#
# DIR (default: $PT_SCENE_SOURCES, else build/scene-sources in the
# repository) is a cache outside version control:
#   DIR/archives/  the packages as downloaded (Debian .deb, npm .tgz)
#   DIR/files/     the extracted source files make_scenes reads
# Files already present with the right sum are not downloaded again.
#
# Needs apt-get (Debian packages; run `apt-get update` first on a fresh
# machine), npm, dpkg-deb, tar, gzip and sha256sum. Exits non-zero with a
# message naming the package when a registry cannot be reached or a sum
# differs; nothing with a wrong sum is kept.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
manifest="$here/sources.txt"
dir=${1:-${PT_SCENE_SOURCES:-$root/build/scene-sources}}

die() {
  echo "fetch_sources.sh: error: $*" >&2
  exit 1
}
for tool in sha256sum tar gzip; do
  command -v "$tool" >/dev/null || die "'$tool' is not installed"
done

sum_of() { sha256sum "$1" | cut -d' ' -f1; }

mkdir -p "$dir/archives" "$dir/files"
dir=$(cd "$dir" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

declare -A kind_of file_of
fetched=0
while read -r tag id kind package version file sha rest; do
  [[ "$tag" == "archive" ]] || continue
  kind_of[$id]=$kind
  file_of[$id]=$file
  target="$dir/archives/$file"
  if [[ -f "$target" && "$(sum_of "$target")" == "$sha" ]]; then
    echo "ok       $file"
    continue
  fi
  rm -f "$target"
  dl="$work/dl-$id"
  mkdir -p "$dl"
  case "$kind" in
    deb)
      command -v apt-get >/dev/null || die "apt-get is needed to download the Debian package $package"
      if ! (cd "$dl" && apt-get download -q -o Acquire::Retries=1 "$package=$version") >"$work/log" 2>&1; then
        cat "$work/log" >&2
        die "could not download Debian package $package version $version. Is the Debian archive reachable? On a fresh machine run 'apt-get update' first; if the version is no longer in the archive, sources.txt needs a new pin."
      fi
      ;;
    npm)
      command -v npm >/dev/null || die "npm is needed to download the npm package $package (apt-get install npm)"
      if ! npm pack "$package@$version" --pack-destination "$dl" --ignore-scripts --silent \
           --fetch-retries=1 --fetch-timeout=60000 >"$work/log" 2>&1; then
        cat "$work/log" >&2
        die "could not download npm package $package@$version. Is the npm registry reachable?"
      fi
      ;;
    *) die "sources.txt: unknown archive kind '$kind' for $id" ;;
  esac
  [[ -f "$dl/$file" ]] || die "downloading $package $version did not produce $file (got: $(ls "$dl"))"
  got=$(sum_of "$dl/$file")
  [[ "$got" == "$sha" ]] || die "$file has SHA-256 $got but sources.txt pins $sha; the registry served different bytes, so the file was not kept"
  mv "$dl/$file" "$target"
  echo "fetched  $file"
  fetched=$((fetched + 1))
done <"$manifest"

# Takes one member out of an archive: a .deb's data, or a .tar.gz/.tgz.
extract_member() {  # archive member out
  case "$1" in
    *.deb) command -v dpkg-deb >/dev/null || die "dpkg-deb is needed to unpack $1"
           dpkg-deb --fsys-tarfile "$1" | tar -xO -f - "./$2" >"$3" ;;
    *) tar -xzO -f "$1" "$2" >"$3" ;;
  esac
}

while read -r tag name sha id steps; do
  [[ "$tag" == "file" ]] || continue
  target="$dir/files/$name"
  if [[ -f "$target" && "$(sum_of "$target")" == "$sha" ]]; then
    echo "ok       files/$name"
    continue
  fi
  rm -f "$target"
  [[ -n "${file_of[$id]:-}" ]] || die "sources.txt: file $name names unknown archive '$id'"
  current="$dir/archives/${file_of[$id]}"
  n=0
  for step in $steps; do
    n=$((n + 1))
    out="$work/step-$name-$n"
    if [[ "$step" == "gunzip" ]]; then
      gzip -dc "$current" >"$out" || die "cannot gunzip $step for $name"
    elif [[ $n -eq 1 ]]; then
      extract_member "$current" "$step" "$out" || die "cannot extract $step from ${file_of[$id]}"
    else
      tar -xzO -f "$current" "$step" >"$out" || die "cannot extract $step for $name"
    fi
    current="$out"
  done
  got=$(sum_of "$current")
  [[ "$got" == "$sha" ]] || die "files/$name has SHA-256 $got but sources.txt pins $sha"
  mv "$current" "$target"
  echo "extracted files/$name"
done <"$manifest"

echo "Sources are in $dir ($fetched archive(s) downloaded)."
