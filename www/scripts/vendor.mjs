// Copies three.js and its OrbitControls / STLLoader from node_modules into www/vendor so the app
// loads nothing from a CDN. The addons' bare `three` imports are rewritten to relative paths.
import { mkdirSync, readFileSync, writeFileSync, existsSync, copyFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const www = join(dirname(fileURLToPath(import.meta.url)), '..');
const three = join(www, 'node_modules', 'three');
const out = join(www, 'vendor');
mkdirSync(out, { recursive: true });
for (const f of ['three.module.js', 'three.core.js']) {
  const src = join(three, 'build', f);
  if (existsSync(src)) copyFileSync(src, join(out, f));
}
for (const [from, to] of [
  ['examples/jsm/controls/OrbitControls.js', 'OrbitControls.js'],
  ['examples/jsm/loaders/STLLoader.js', 'STLLoader.js'],
]) {
  const text = readFileSync(join(three, from), 'utf8').replace(/from\s+['"]three['"]/g, "from './three.module.js'");
  writeFileSync(join(out, to), text);
}
copyFileSync(join(three, 'LICENSE'), join(out, 'three.LICENSE'));
console.log('vendor: three.js copied to www/vendor');
