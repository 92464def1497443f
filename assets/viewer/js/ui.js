// The control panel (top left) and the probe popup: reads the user's
// settings, shows the solve's progress, the connection, the false-colour
// legend, and probe results.

import { STEPS, bandColour, legendBoundaries, format3 } from './falsecolor.js';

/** Units of the false-colour displays. */
const UNITS = { luminance: 'cd/m²', illuminance: 'lx' };

const byId = (id) => document.getElementById(id);

/** A signed number with one decimal: +1.0, −2.5. */
function signed(v) {
  return (v >= 0 ? '+' : '−') + Math.abs(v).toFixed(1);
}

/**
 * The server's default false-colour maximum for a display:
 * status.luminance_max (cd/m²) or status.illuminance_max (lx).
 */
function serverMax(status, display) {
  if (!status) return null;
  const v = display === 'illuminance' ? status.illuminance_max : status.luminance_max;
  return typeof v === 'number' && v > 0 && Number.isFinite(v) ? v : null;
}

/**
 * Builds the legend: one swatch per band, highest at the top, labels at
 * the band boundaries (legendBoundaries), and the unit above.
 */
function renderLegend(element, max, log, unit) {
  const bounds = legendBoundaries(max, log);
  const swatchHeight = 14;
  element.textContent = '';
  const header = document.createElement('div');
  header.className = 'unit';
  header.textContent = unit + (log ? ' (log, 3 decades)' : '');
  element.appendChild(header);
  const scale = document.createElement('div');
  scale.className = 'scale';
  for (let b = STEPS - 1; b >= 0; b--) {
    const swatch = document.createElement('div');
    swatch.className = 'swatch';
    swatch.style.background = `rgb(${bandColour(b).join(',')})`;
    scale.appendChild(swatch);
  }
  for (let i = 0; i <= STEPS; i++) {
    const tick = document.createElement('div');
    tick.className = 'tick';
    tick.style.top = `${(STEPS - i) * swatchHeight}px`;
    tick.textContent = format3(bounds[i]);
    scale.appendChild(tick);
  }
  element.appendChild(scale);
}

/** The progress line of a status message. */
function progressText(s) {
  const parts = [
    s.state,
    `${s.shots ?? 0} shots`,
    `unshot ${(100 * (s.unshot ?? 0)).toFixed(2)} %`,
    `${(s.elapsed_s ?? 0).toFixed(1)} s`,
    `${s.vertices ?? 0} vertices`,
  ];
  if (typeof s.triangles === 'number') parts.push(`${s.triangles} triangles`);
  if (s.stop_reason) parts.push(`(${s.stop_reason})`);
  if (typeof s.ambient_progress === 'number') {
    parts.push(`ambient term ${(100 * s.ambient_progress).toFixed(0)} %`);
  }
  if (s.error) parts.push(`error: ${s.error}`);
  return parts.join(' · ');
}

/**
 * Wires the panel.
 * @param {{changed:()=>void, control:(action:string)=>void,
 *   savePng:()=>void, toggleMode:()=>void, home:()=>void}} handlers
 */
export function createUi(handlers) {
  const el = {
    scene: byId('scene-name'),
    exposure: byId('exposure'),
    exposureAuto: byId('exposure-auto'),
    exposureValue: byId('exposure-value'),
    display: byId('display'),
    falsecolour: byId('falsecolour'),
    fcMax: byId('fc-max'),
    fcUnit: byId('fc-unit'),
    fcLog: byId('fc-log'),
    legend: byId('legend'),
    connection: byId('connection'),
    progress: byId('progress'),
    pause: byId('pause'),
    resume: byId('resume'),
    stop: byId('stop'),
    mode: byId('mode'),
    home: byId('home'),
    savePng: byId('save-png'),
    probe: byId('probe'),
    marker: byId('probe-marker'),
    message: byId('message'),
    panel: byId('panel'),
    panelToggle: byId('panel-toggle'),
  };
  /** The user's own false-colour maxima; null follows the server. */
  const userMax = { luminance: null, illuminance: null };
  let status = null;

  const display = () => el.display.value;
  const offset = () => Number(el.exposure.value) || 0;

  /** max for the current false-colour display: the user's or the server's (1 before any). */
  function currentMax() {
    const d = display();
    return userMax[d] ?? serverMax(status, d) ?? 1;
  }

  /** Refreshes the exposure label, the max field and the legend. */
  function refresh() {
    const auto = status && typeof status.exposure === 'number' ? status.exposure : 0;
    el.exposureValue.textContent =
      `offset ${signed(offset())} stops → exposure ${signed(auto + offset())} (auto ${signed(auto)})`;
    const d = display();
    const falseColour = d !== 'radiance';
    el.falsecolour.hidden = !falseColour;
    if (!falseColour) return;
    const max = currentMax();
    if (document.activeElement !== el.fcMax) el.fcMax.value = String(Number(max.toPrecision(6)));
    el.fcUnit.textContent = UNITS[d];
    renderLegend(el.legend, max, el.fcLog.checked, UNITS[d]);
  }

  const changed = () => {
    refresh();
    handlers.changed();
  };

  el.exposure.addEventListener('input', changed);
  el.exposureAuto.addEventListener('click', () => {
    el.exposure.value = '0';
    changed();
  });
  el.display.addEventListener('change', changed);
  el.fcLog.addEventListener('change', changed);
  // ?display=luminance|illuminance opens in false colour (&log=1 on a log
  // scale): a link to show a client.
  const parameters = new URLSearchParams(location.search);
  if (['luminance', 'illuminance'].includes(parameters.get('display'))) {
    el.display.value = parameters.get('display');
    el.fcLog.checked = parameters.get('log') === '1';
  }
  el.fcMax.addEventListener('input', () => {
    const v = Number(el.fcMax.value);
    const d = display();
    if (el.fcMax.value.trim() === '') userMax[d] = null;
    else if (Number.isFinite(v) && v > 0) userMax[d] = v;
    else return;
    changed();
  });
  el.fcMax.addEventListener('blur', refresh);
  el.pause.addEventListener('click', () => handlers.control('pause'));
  el.resume.addEventListener('click', () => handlers.control('resume'));
  el.stop.addEventListener('click', () => handlers.control('stop'));
  el.mode.addEventListener('click', () => handlers.toggleMode());
  el.home.addEventListener('click', () => handlers.home());
  el.savePng.addEventListener('click', () => handlers.savePng());
  const fold = (folded) => {
    el.panel.classList.toggle('folded', folded);
    el.panelToggle.textContent = folded ? '+' : '–';
  };
  el.panelToggle.addEventListener('click', () => fold(!el.panel.classList.contains('folded')));
  // A small window starts with the panel folded: the view stays clickable.
  if (window.innerWidth < 640 || window.innerHeight < 480) fold(true);
  // ?panel=0 hides the panel; ?panel=1 keeps it shown; by default it
  // fades out while the user is idle.
  const panelParameter = new URLSearchParams(location.search).get('panel');
  if (panelParameter === '0') el.panel.hidden = true;
  else if (panelParameter !== '1') hideWhenIdle(el.panel);
  refresh();

  return {
    /**
     * What the renderer needs: exposure = server's automatic exposure +
     * the user's offset (stops), the display, the false-colour max and log.
     */
    view() {
      const auto = status && typeof status.exposure === 'number' ? status.exposure : 0;
      return { exposure: auto + offset(), display: display(), max: currentMax(), log: el.fcLog.checked };
    },
    showHello(hello) {
      el.scene.textContent = hello.scene || '';
      if (hello.scene) document.title = `isorad view — ${hello.scene}`;
    },
    showStatus(s) {
      status = s;
      el.progress.textContent = progressText(s);
      const done = s.state === 'done';
      el.pause.disabled = done;
      el.resume.disabled = done;
      el.stop.disabled = done;
      el.pause.classList.toggle('active', s.state === 'paused');
      refresh();
    },
    showConnection(up) {
      el.connection.textContent = up ? 'connected' : 'disconnected — retrying';
      el.connection.classList.toggle('down', !up);
    },
    showMode(mode) {
      el.mode.textContent = mode === 'walk' ? 'Orbit' : 'Walk';
      el.mode.title = mode === 'walk'
        ? 'Back to orbit (drag turns about the target)'
        : 'Walk (WASD / arrows, Q/E, Shift ×3, drag turns)';
    },
    /** Shows a transient message (errors), hidden after `ms` (0: stays). */
    message(text, ms = 4000) {
      el.message.textContent = text;
      el.message.hidden = false;
      if (ms > 0) {
        clearTimeout(el.message.timer);
        el.message.timer = setTimeout(() => (el.message.hidden = true), ms);
      }
    },
    /** Hides the message. */
    clearMessage() {
      clearTimeout(el.message.timer);
      el.message.hidden = true;
    },
    /** Shows "probing…" at canvas point (x, y). */
    probePending(x, y) {
      const p = el.probe;
      clearTimeout(p.timer);
      for (const a of ['data-illuminance-lx', 'data-luminance-cd-m2', 'data-surface', 'data-error']) {
        p.removeAttribute(a);
      }
      p.textContent = 'probing…';
      this.placeProbe([x, y]);
    },
    /** Shows a probe answer: `ok` with the server's JSON, or its error. */
    probeResult(ok, body) {
      const p = el.probe;
      p.textContent = '';
      clearTimeout(p.timer);
      const line = (text, cls) => {
        const div = document.createElement('div');
        div.textContent = text;
        if (cls) div.className = cls;
        p.appendChild(div);
      };
      if (ok) {
        p.setAttribute('data-illuminance-lx', String(body.illuminance_lx));
        p.setAttribute('data-luminance-cd-m2', String(body.luminance_cd_m2));
        p.setAttribute('data-surface', String(body.surface ?? ''));
        line(`${format3(body.illuminance_lx)} lx`);
        line(`${format3(body.luminance_cd_m2)} cd/m²`);
        line(String(body.surface ?? ''));
      } else {
        p.setAttribute('data-error', String(body.error ?? 'error'));
        line(String(body.error ?? 'probe failed'), 'error');
      }
    },
    /** Moves the popup and marker to canvas point xy, or hides the marker when null. */
    placeProbe(xy) {
      if (!xy) {
        el.marker.hidden = true;
        return;
      }
      el.marker.hidden = false;
      el.marker.style.left = `${xy[0]}px`;
      el.marker.style.top = `${xy[1]}px`;
      el.probe.hidden = false;
      // Beside the point, flipped to its left / above it near the window's edges.
      const w = el.probe.offsetWidth;
      const h = el.probe.offsetHeight;
      const x = xy[0] + 10 + w > window.innerWidth ? xy[0] - 10 - w : xy[0] + 10;
      const y = xy[1] + 10 + h > window.innerHeight ? xy[1] - 10 - h : xy[1] + 10;
      el.probe.style.left = `${Math.max(0, x)}px`;
      el.probe.style.top = `${Math.max(0, y)}px`;
    },
    /** Hides the popup and the marker, after `ms` ms when given. */
    hideProbe(ms = 0) {
      const hide = () => {
        el.probe.hidden = true;
        el.marker.hidden = true;
      };
      clearTimeout(el.probe.timer);
      if (ms > 0) el.probe.timer = setTimeout(hide, ms);
      else hide();
    },
  };
}

/** Milliseconds without input after which the panel fades out. */
const IDLE_MS = 5000;

/**
 * Shows `panel` while the user is at work and fades it out after IDLE_MS
 * without pointer or key input (unless the pointer is over it or one of
 * its fields has the focus), so the view is the whole picture: what a
 * client watching sees, and what a screenshot of the page shows. It
 * starts hidden and appears with the first input.
 */
function hideWhenIdle(panel) {
  let timer = null;
  const idle = () => {
    if (panel.matches(':hover') || panel.contains(document.activeElement)) {
      timer = setTimeout(idle, IDLE_MS);
      return;
    }
    panel.classList.add('idle');
  };
  const active = () => {
    panel.classList.remove('idle');
    clearTimeout(timer);
    timer = setTimeout(idle, IDLE_MS);
  };
  panel.classList.add('idle');
  for (const type of ['pointermove', 'pointerdown', 'keydown', 'wheel', 'touchstart']) {
    window.addEventListener(type, active, { passive: true });
  }
}
