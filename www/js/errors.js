// The error box: a title, the core's message as it is, and the advice for its code.
import { $, el } from './dom.js';
import { adviceFor } from './advice.js';

/**
 * Shows `err` (an Error with `.code`, or `{code, message}`) under `title`; an error without a
 * code gets the advice of `area`, the area of the step that failed.
 */
export function showError(title, err, area = null) {
  const box = $('error');
  const code = err?.code ?? null;
  box.replaceChildren(el('strong', { textContent: title }), el('div', { textContent: err?.message ?? String(err), 'data-testid': 'error-message' }));
  const advice = adviceFor(code) ?? (area ? adviceFor(`${area}.`) : null);
  if (advice) box.append(el('div', { textContent: `What to do: ${advice.text}`, 'data-testid': 'error-advice', dataset: { advice: advice.key } }));
  if (code) box.dataset.code = code;
  else delete box.dataset.code;
  box.hidden = false;
  box.scrollIntoView?.({ block: 'nearest' });
}

export function clearError() {
  const box = $('error');
  box.hidden = true;
  box.replaceChildren();
  delete box.dataset.code;
}
