// Offline after the first visit: network first for the app's own files, falling back to the
// cache (so an update is picked up when online). Only same-origin GETs are handled.
const CACHE = 'warpslice-v7';
const SHELL = ['./', './index.html', './style.css', './worker.js', './icon.svg', './manifest.webmanifest',
  './js/main.js', './js/state.js', './js/dom.js', './js/worker-client.js', './js/machines.js', './js/params.js', './js/forms.js',
  './js/settings.js', './js/steps.js', './js/view.js', './js/preview.js', './js/advice.js', './js/errors.js', './js/check.js', './js/builtin.js', './js/slicer-form.js', './js/overhang.js', './js/head.js',
  './vendor/three.module.js', './vendor/three.core.js', './vendor/OrbitControls.js', './vendor/STLLoader.js',
  './pkg/warpslice.js', './pkg/warpslice_bg.wasm'];

self.addEventListener('install', (e) => {
  e.waitUntil(caches.open(CACHE).then((c) => c.addAll(SHELL)).then(() => self.skipWaiting()));
});
self.addEventListener('activate', (e) => {
  e.waitUntil(caches.keys().then((ks) => Promise.all(ks.filter((k) => k !== CACHE).map((k) => caches.delete(k)))).then(() => self.clients.claim()));
});
self.addEventListener('fetch', (e) => {
  const url = new URL(e.request.url);
  if (e.request.method !== 'GET' || url.origin !== self.location.origin) return;
  e.respondWith(
    fetch(e.request)
      .then((r) => {
        if (r.ok) {
          const copy = r.clone();
          caches.open(CACHE).then((c) => c.put(e.request, copy));
        }
        return r;
      })
      .catch(() => caches.match(e.request).then((r) => r || Response.error())),
  );
});
