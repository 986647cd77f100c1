// The error box: a title, the core's message as it is, and the advice for its code.
import { $, el } from './dom.js';
import { adviceFor } from './advice.js';

/**
 * Shows `err` (an Error with `.code`, or `{code, message}`) under `title`; an error without a
 * code gets the advice of `area`, the area of the step that failed. An error shown with a
 * `source` (`'custom-machine'`: the core refused the custom machine JSON) stays until that
 * source clears it (`clearError(source)`); any other error replaces it.
 */
export function showError(title, err, area = null, source = null) {
  const box = $('error');
  const code = err?.code ?? null;
  box.replaceChildren(el('strong', { textContent: title }), el('div', { textContent: err?.message ?? String(err), 'data-testid': 'error-message' }));
  const advice = adviceFor(code) ?? (area ? adviceFor(`${area}.`) : null);
  if (advice) box.append(el('div', { textContent: `What to do: ${advice.text}`, 'data-testid': 'error-advice', dataset: { advice: advice.key } }));
  if (code) box.dataset.code = code;
  else delete box.dataset.code;
  if (source) box.dataset.source = source;
  else delete box.dataset.source;
  box.hidden = false;
  box.scrollIntoView?.({ block: 'nearest' });
}

/**
 * Hides the error box: `clearError()` an error of the steps, `clearError(source)` only an error
 * shown with that `source` (a step starting over leaves the custom machine's error shown).
 */
export function clearError(source = null) {
  const box = $('error');
  if (!box.hidden && (box.dataset.source ?? null) !== source) return;
  box.hidden = true;
  box.replaceChildren();
  delete box.dataset.code;
  delete box.dataset.source;
}
