// The likely causes of a difference with a case's reference (the known
// bugs nearest to it, as the grader names them; X-Hints of /api/diff), in
// words under the verdict.

// Fills `box` with `likely`'s hints, or the line that no known bug is
// close; empties and hides it for a render that matches (or `likely` null).
export function showHints(box, likely) {
  box.replaceChildren();
  const hints = likely ? likely.hints : [];
  for (const [i, h] of hints.entries()) {
    const p = document.createElement('p');
    const head = document.createElement('b');
    head.textContent = `Likely cause ${i + 1} of ${hints.length}: `;
    const where = document.createElement('span');
    where.className = 'where';
    where.textContent = `Look at ${h.function} in ${h.file}` +
                        (h.section ? `, and read "${h.section}" in ${h.readme}.` : `, and read ${h.readme}.`);
    p.append(head, h.text, document.createElement('br'), where);
    box.append(p);
  }
  if (likely && !hints.length && likely.note) {
    const p = document.createElement('p');
    p.textContent = likely.note;
    box.append(p);
  }
  box.hidden = !box.childElementCount;
}
