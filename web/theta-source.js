// Where the editor's volume tensor comes from: the session's memory (tensors of this model, per
// level and scheme), the IndexedDB cache, or the worker. Until it arrives the editor runs
// matrix-free; the rule of when a tensor is worth it is the API's (chooseGradientPath).
import { thetaKey } from './theta-cache.js';
import { thetaInWorker } from './editor-rebuild.js';
import { thetaName, showTheta, showProgress, notice, noticeText, showCacheStatus } from './readouts.js';

export class ThetaSource {
  /** The cache (ThetaCache) once open; `prefetch`: { key, bytes: Promise } read ahead at start-up. */
  cache = null;
  prefetch = null;
  key = null;
  source = null;
  pending = false;
  status = '';
  #generation = 0;
  #workerStarted = null; // { key, at }: the cached theta^e being read in the editor worker

  /**
   * @param {import('../lib/three/session.mjs').EditingSession} session
   * @param {{ jobs: import('./theta-jobs.js').ThetaJobs, stats: object, showCache: (entries, note?) => void,
   *   rebuild?: (target, apply, options) => Promise<{ swapped, error }> }} deps `rebuild`: makes the editor in the
   *   worker as main.js rebuildBig does (drags wait), here with a cached theta^e read and handed over there
   */
  constructor(session, { jobs, stats, showCache, rebuild = null }) {
    this.session = session;
    this.rebuild = rebuild;
    this.jobs = jobs;
    this.stats = stats;
    this.showCache = showCache;
  }

  currentKey() {
    const { model, level, scheme, alpha, beta } = this.session;
    return thetaKey({ fingerprint: model.fingerprint, scheme, alpha, beta, level });
  }

  cancel() {
    this.#generation++;
    this.jobs.cancel();
    showProgress(null);
  }

  /** The cancel button: stops the worker's job (the editor stays matrix-free). */
  cancelJob() {
    const generation = this.#generation;
    this.jobs.cancel();
    if (generation === this.#generation) showProgress(null);
  }

  /** source: 'computed' | 'cache' | null; pending: null source while theta is on its way (else 'none'). */
  #setState(source, status, pending = true) {
    this.source = source;
    this.pending = source === null && pending;
    this.status = status;
    showTheta(this);
  }

  /** `theta`: the tensor, or its info when it was handed to an editor made in the worker. */
  #arrived(source, theta, started, where = '') {
    const duration = (ms) => (ms < 1000 ? `${Math.round(ms)} ms` : `${(ms / 1000).toFixed(1)} s`);
    const info = typeof theta.info === 'function' ? theta.info() : theta;
    this.#setState(source, `${thetaName(info.level)}: ${(info.nnzStored / 1e6).toFixed(2)} million numbers, ` +
      `${(info.bytes / 2 ** 20).toFixed(1)} MB, ready in ${duration(performance.now() - started)}${where}`);
    this.stats.thetaReadyAt ??= performance.now();
  }

  /**
   * Puts theta^e of the current model, scheme and level into the editor: from the session's
   * memory, from the cache or from the worker. A cache lookup at start-up takes a few hundred ms, so
   * when the cache probably has nothing (no session said so) the worker starts at once beside the
   * lookup, and a hit cancels it.
   */
  async request() {
    this.cancel();
    const generation = this.#generation;
    const stale = () => generation !== this.#generation;
    const session = this.session;
    const key = this.currentKey();
    this.key = key;
    const started = performance.now();

    const choice = session.gradientChoice();
    if (session.editor.path() === 'polynomial') {
      // A coarse cage: the editor built the cage polynomial from the fine mesh (small, no hand-off).
      this.#setState(null, 'not needed: the cage polynomial is in use', false);
      this.stats.thetaReadyAt ??= performance.now();
      return;
    }
    if (choice.path !== 'tensor') {
      const { estimate } = choice;
      this.#setState(null, choice.reason ?? `not computed: ${thetaName(session.level)} would need about ` +
        `${Math.round(estimate.bytes / 2 ** 20)} MB and ${(estimate.milliseconds / 1000).toFixed(0)} s; editing runs matrix-free`, false);
      return;
    }
    const stored = session.storedTheta();
    if (stored && session.editor.path() === 'tensor') {
      const inWorker = this.#workerStarted?.key === key;
      const where = stored.theta ? '' : ' (read and handed to the editor in a worker)';
      this.#arrived(stored.source, stored.theta ?? stored.info, inWorker ? this.#workerStarted.at : started, where);
      this.#workerStarted = null;
      return;
    }
    this.#setState(null, this.cache?.available ? 'looking in the cache…' : '');

    let job = null;
    if (this.cache?.available) {
      // read ahead at start-up (main.js): a small θ's bytes; null when absent or big (read in the worker)
      const prefetched = this.prefetch?.key === key ? this.prefetch.bytes : null;
      this.prefetch = null;
      const lookup = performance.now();
      const early = prefetched ? await prefetched : null;
      if (stale()) return;
      if (!early && this.rebuild && await this.#fromCacheInWorker(key, started, stale)) return;
      if (stale()) return;
      if (!prefetched) job = this.#startJob(generation);
      const bytes = early ?? (await this.cache.get(key));
      this.stats.cacheLookupMs ??= performance.now() - lookup;
      if (stale()) return;
      if (bytes) {
        let theta = null, problem;
        try {
          const read = performance.now();
          theta = session.mrvol.readTheta(bytes);
          const use = performance.now();
          const used = session.useTheta(theta, 'cache');
          this.stats.cacheLoad = { get: read - lookup, readTheta: use - read, useTheta: performance.now() - use };
          if (!used.ok) problem = used.reason;
        } catch (e) {
          problem = e.message;
        }
        if (!problem) {
          if (job) this.jobs.cancel();
          showProgress(null);
          this.#arrived('cache', theta, started);
          return;
        }
        theta?.delete();
        notice(`The cached θ was unusable (${problem}): it was deleted and is being recomputed.`);
        await this.cache.delete(key);
        this.refreshCacheList();
        if (stale()) return;
      }
    }
    this.#finishJob(generation, key, started, job ?? this.#startJob(generation));
  }

  /**
   * A big cached theta^e (`source`: 'cache', or 'computed' just now and stored): the editor made
   * with it in the editor worker (read from IndexedDB there),
   * the page only taking the editor over. True when that was done (or cancelled: the editor kept
   * runs matrix-free); false to go on here (small or absent; or a path the worker cannot make, said).
   */
  async #fromCacheInWorker(key, started, stale, source = 'cache') {
    const session = this.session;
    const bytes = await this.cache.size(key);
    if (stale()) return true;
    const { worker, why } = thetaInWorker(session, bytes);
    if (!worker) {
      if (why) this.#setState(null, `reading the cached θ on the page's thread (${why})`);
      return false;
    }
    const target = { level: session.level, scheme: session.scheme };
    this.#workerStarted = { key, at: started };
    this.#setState(null, `${source === 'cache' ? 'reading the cached θ' : 'reading θ back'} in a worker (editing waits)`);
    const { swapped, error } = await this.rebuild(target,
      (mr, info) => session.adoptRebuilt(mr, target, { record: false, theta: { source, info } }), { theta: { key } });
    if (swapped) return true; // the editor swapped in asked for θ again: request() found it in the editor
    this.#workerStarted = null;
    if (!error) {
      this.#setState(null, 'cancelled: editing runs matrix-free', false);
      return true;
    }
    notice(`The cached θ could not be read in a worker (${error.message}): it is read on the page's thread.`);
    return false;
  }

  /** Posts the theta job to the worker. Resolves to { result } or { error }; never rejects. */
  #startJob(generation) {
    const stale = () => generation !== this.#generation;
    const session = this.session;
    const { level, scheme, alpha, beta } = session;
    this.#setState(null, 'computing in a worker (editing runs matrix-free meanwhile)');
    showProgress(0, `Computing ${thetaName(level)} (${scheme})`);
    const posted = performance.now();
    return this.jobs.compute({
      meshKey: session.model.fingerprint,
      positions: session.model.mr.positions(),
      faces: session.model.faces,
      level, scheme, alpha, beta,
    }, (fraction) => {
      if (!stale()) showProgress(fraction, `Computing ${thetaName(level)} (${scheme}) ${Math.round(fraction * 100)}%`);
    }).then((result) => ({ result, posted }), (error) => ({ error }));
  }

  async #finishJob(generation, key, started, job) {
    const stale = () => generation !== this.#generation;
    const { result, posted, error } = await job;
    if (stale()) return;
    showProgress(null);
    if (error) {
      if (error.cancelled) this.#setState(null, 'cancelled: editing runs matrix-free', false);
      else this.#setState(null, `failed: ${error.message}; editing runs matrix-free`, false);
      return;
    }
    const received = performance.now();
    performance.mark('mrvol: θ received'); // a trace's window of storing and handing it over starts here
    this.stats.thetaMs = result.ms;
    let cached = null;
    // a big θ goes to the editor worker through the cache (read and handed over there, not here)
    if (this.cache?.available && this.rebuild && thetaInWorker(this.session, result.bytes.byteLength).worker) {
      cached = await this.#store(key, result.bytes);
      if (stale()) return;
      if (cached.ok && await this.#fromCacheInWorker(key, started, stale, 'computed')) return;
    }
    let theta;
    try {
      theta = this.session.mrvol.readTheta(result.bytes);
    } catch (e) {
      this.#setState(null, `the worker's θ was unreadable (${e.message}); editing runs matrix-free`, false);
      return;
    }
    const used = this.session.useTheta(theta, 'computed');
    if (!used.ok) {
      theta.delete();
      this.#setState(null, `θ was refused (${used.reason}); editing runs matrix-free`, false);
      return;
    }
    this.stats.thetaJob = { roundTrip: received - posted, ...result.timings, readAndUse: performance.now() - received };
    this.#arrived('computed', theta, started);
    if (this.cache?.available && !cached) await this.#store(key, result.bytes);
  }

  /** Writes a θ file to the cache, saying a failure (and its end) in words; resolves to put's { ok, reason }. */
  async #store(key, bytes) {
    const stored = await this.cache.put(key, bytes, { model: this.session.model?.name });
    if (!stored.ok) {
      notice(`θ is not cached: ${stored.reason}. Editing goes on; θ will be computed again next time.`);
      showCacheStatus(`IndexedDB (the last write failed: ${stored.reason})`);
    } else {
      // a failure said earlier is over
      if (noticeText().startsWith('θ is not cached')) notice('');
      showCacheStatus('IndexedDB');
    }
    this.refreshCacheList();
    return stored;
  }

  /** Forgets the tensor of the current level (memory and cache) and computes it again. */
  async recompute() {
    const key = this.currentKey();
    this.session.forgetTheta();
    await this.cache?.delete(key);
    return this.request();
  }

  async refreshCacheList() {
    if (!this.cache?.available) {
      this.showCache([], `IndexedDB unavailable (${this.cache?.reason ?? 'not opened'}): no cache`);
      return;
    }
    this.showCache(await this.cache.list());
  }

  async clearCache() {
    await this.cache?.clear();
    this.refreshCacheList();
  }
}
