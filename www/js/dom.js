// Small DOM helpers shared by the modules: lookups, definition lists, download links.

/** The element with this id. */
export const $ = (id) => document.getElementById(id);

/** `document.createElement(tag)` with properties / attributes set and children appended. */
export function el(tag, props = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(props)) {
    if (v == null || v === false) continue;
    if (k === 'dataset') {
      for (const [dk, dv] of Object.entries(v)) if (dv != null) e.dataset[dk] = String(dv);
    } else if (k === 'className' || k === 'textContent' || k === 'htmlFor' || k === 'value' || k === 'checked') e[k] = v;
    else e.setAttribute(k, v === true ? '' : String(v));
  }
  e.append(...children.filter((c) => c != null));
  return e;
}

/** Fills a `<dl>` with `[term, value]` rows. */
export function info(dl, rows) {
  dl.replaceChildren();
  for (const [k, v] of rows) dl.append(el('dt', { textContent: k }), el('dd', { textContent: v }));
}

/** Points the download link `id` at `blob` (null: disables it). */
export function setDownload(id, blob, name) {
  const a = $(id);
  a.onclick = null; // a pending `setLazyDownload` is replaced
  if (a.href?.startsWith('blob:')) URL.revokeObjectURL(a.href);
  if (!blob) {
    a.removeAttribute('href');
    a.classList.add('disabled');
    a.setAttribute('aria-disabled', 'true');
    return;
  }
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.classList.remove('disabled');
  a.removeAttribute('aria-disabled');
}

/**
 * `setDownload` of a file written when it is first clicked (`make()` → Blob): a large JSON (a
 * report listing 88 000 collisions) is not written on the main thread unless it is asked for.
 */
export function setLazyDownload(id, make, name) {
  setDownload(id, new Blob([]), name);
  // the click's default action follows the href set here (the file, not the placeholder)
  $(id).onclick = () => setDownload(id, make(), name);
}

/** A file name without its extension, safe for a download name. */
export function baseName(name) {
  return (name || 'model').replace(/\.[^.]*$/, '').replace(/[^\w.-]+/g, '_') || 'model';
}

/** The core's Aabb ({min: [x,y,z], max: [x,y,z]}) as {min: {x,y,z}, max: {x,y,z}}. */
export function box3(b) {
  const v = (a) => (Array.isArray(a) ? { x: a[0], y: a[1], z: a[2] } : a);
  return b ? { min: v(b.min), max: v(b.max) } : b;
}
