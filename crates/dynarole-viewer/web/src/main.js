// The viewer page: reads the recording inlined in the page, builds the scene, the timeline
// (play, speed, scrub, previous/next event, next fault), the state panel, the swimlanes and
// the source with the running statements highlighted. Everything is in this one file's
// bundle: the page fetches nothing.
import { World, lastAtOrBefore } from './world.js';
import { Scene } from './scene.js';
import { Timeline, Swimlanes, Legend } from './timeline.js';
import { SourcePanel, StatePanel } from './panels.js';
import { runProbe } from './probe.js';

const SPEEDS = [0.25, 0.5, 1, 2, 4, 8, 16, 32, 64];
const FLASH_MS = 600;
const PACKET_SHOWN_MS = 150;

function element(tag, attributes = {}, text = '') {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, v);
  if (text) e.textContent = text;
  return e;
}

class Viewer {
  constructor(recording, vocabulary) {
    this.rec = recording;
    this.world = new World(recording);
    this.time = 0;
    this.playing = false;
    this.speed = 1;
    this.showNames = false;
    this.showPackets = false;
    this.packets = recording.packets.slice().sort((a, b) => a.start_ms - b.start_ms);
    this.events = recording.events;
    this.layout();
    this.scene = new Scene(this.view, recording);
    this.timeline = new Timeline(this.timelineBox, recording, vocabulary, (t) => this.seek(t));
    this.legend = new Legend(this.legendBox, vocabulary);
    this.swimlanes = new Swimlanes(this.swimBox, recording, vocabulary, (t) => this.seek(t));
    this.source = new SourcePanel(this.sourceBox, recording);
    this.state = new StatePanel(this.stateBox, recording);
    this.labels = recording.modules.map((m) => {
      const label = element('div', { class: 'label' }, m.name);
      this.view.appendChild(label);
      return label;
    });
    this.hovered = null;
    this.view.addEventListener('mousemove', (e) => {
      const r = this.view.getBoundingClientRect();
      this.hovered = this.scene.pick(e.clientX - r.left, e.clientY - r.top);
      this.draw();
    });
    this.scene.controls.addEventListener('change', () => this.draw());
    window.addEventListener('resize', () => {
      this.scene.resize();
      this.draw();
    });
    this.seek(0);
  }

  layout() {
    document.title = `dynarole view: ${this.rec.title}`;
    const root = element('div', { id: 'app' });
    const header = element('header');
    header.appendChild(element('h1', {}, this.rec.title));
    header.appendChild(element('span', { id: 'summary' }, this.rec.summary[0] || ''));
    const omitted = this.rec.omitted_packets || 0;
    const omittedEvents = this.rec.omitted_packet_events || 0;
    if (omitted || omittedEvents) {
      const note = `not recorded: ${omitted} packets, ${omittedEvents} trace lines of dropped packets (the recording keeps the first ones)`;
      header.appendChild(element('span', { id: 'omitted' }, note));
    }
    this.view = element('div', { id: 'view' });
    const controls = element('div', { id: 'controls' });
    const button = (id, text, title, action) => {
      const b = element('button', { id, title }, text);
      b.addEventListener('click', action);
      controls.appendChild(b);
      return b;
    };
    this.playButton = button('play', 'Play', 'play or pause (space)', () => this.toggle());
    button('prev-event', '|<', 'previous event', () => this.step(-1));
    button('next-event', '>|', 'next event', () => this.step(1));
    button('next-fault', 'Next fault', 'jump to the next fault or violation', () => this.nextFault());
    this.speedSelect = element('select', { id: 'speed', title: 'speed' });
    for (const s of SPEEDS) {
      const o = element('option', { value: String(s) }, `${s}x`);
      if (s === 1) o.selected = true;
      this.speedSelect.appendChild(o);
    }
    this.speedSelect.addEventListener('change', () => (this.speed = Number(this.speedSelect.value)));
    controls.appendChild(this.speedSelect);
    this.scrub = element('input', { id: 'scrub', type: 'range', min: '0', max: String(this.rec.end_ms), step: 'any', value: '0' });
    this.scrub.addEventListener('input', () => this.seek(Number(this.scrub.value)));
    controls.appendChild(this.scrub);
    this.clock = element('span', { id: 'clock' });
    controls.appendChild(this.clock);
    button('reset-camera', 'Camera', 'reset the camera', () => {
      this.scene.resetCamera(this.world.at(this.time).poses);
      this.draw();
    });
    const toggle = (id, text, key) => {
      const label = element('label', { class: 'toggle' });
      const box = element('input', { id, type: 'checkbox' });
      box.addEventListener('change', () => {
        this[key] = box.checked;
        this.seek(this.time);
      });
      label.append(box, document.createTextNode(text));
      controls.appendChild(label);
    };
    toggle('names', 'names', 'showNames');
    toggle('packets', 'packets', 'showPackets');
    button('png', 'PNG', 'save the view as PNG', () => this.savePng());
    this.timelineBox = element('div', { id: 'timeline' });
    this.legendBox = element('div', { id: 'legend' });
    this.swimBox = element('div', { id: 'swimlanes' });
    this.sourceBox = element('div', { id: 'source' });
    this.stateBox = element('div', { id: 'state' });
    const side = element('div', { id: 'side' });
    side.append(this.stateBox, this.sourceBox);
    const main = element('div', { id: 'main' });
    main.append(this.view, side);
    root.append(header, main, controls, this.timelineBox, this.legendBox, this.swimBox);
    document.body.appendChild(root);
    document.addEventListener('keydown', (e) => {
      if (e.key === ' ' && e.target === document.body) {
        e.preventDefault();
        this.toggle();
      }
    });
  }

  toggle() {
    this.playing = !this.playing;
    this.playButton.textContent = this.playing ? 'Pause' : 'Play';
    if (this.playing) {
      if (this.time >= this.rec.end_ms) this.seek(0);
      this.last = performance.now();
      requestAnimationFrame((now) => this.tick(now));
    }
  }

  tick(now) {
    if (!this.playing) return;
    const elapsed = now - this.last;
    this.last = now;
    const next = Math.min(this.rec.end_ms, this.time + elapsed * this.speed);
    this.seek(next);
    if (next >= this.rec.end_ms) {
      this.toggle();
      return;
    }
    requestAnimationFrame((t) => this.tick(t));
  }

  // Moves to the event after (dir 1) or before (dir -1) the current time.
  step(dir) {
    const times = this.events.map((e) => e.time_ms);
    const t = dir > 0 ? times.find((x) => x > this.time) : [...times].reverse().find((x) => x < this.time);
    if (t !== undefined) this.seek(t);
  }

  nextFault() {
    const m = this.rec.markers.find((x) => x.time_ms > this.time);
    if (m) this.seek(m.time_ms);
  }

  seek(t) {
    this.time = Math.max(0, Math.min(this.rec.end_ms, t));
    this.scrub.value = String(this.time);
    this.current = this.world.at(this.time);
    this.clock.textContent = `${(this.time / 1000).toFixed(3)} s / ${(this.rec.end_ms / 1000).toFixed(3)} s`;
    const flashing = new Set();
    for (const m of this.rec.markers) {
      if (m.time_ms <= this.time && this.time - m.time_ms < FLASH_MS) m.modules.forEach((i) => flashing.add(i));
    }
    const latchedMales = new Set();
    for (const [a, ca, b, cb] of this.current.latches) {
      if (this.rec.connectors[ca].male) latchedMales.add(a * 64 + ca);
      if (this.rec.connectors[cb].male) latchedMales.add(b * 64 + cb);
    }
    this.scene.show(this.current, flashing, latchedMales);
    this.scene.showPackets(this.current, this.showPackets ? this.packetsAt(this.time) : []);
    const running = this.rec.motions.filter((m) => m.start_ms <= this.time && (this.time < m.end_ms || (m.outcome === 'running' && m.end_ms <= m.start_ms)));
    this.source.highlight(running.map((m) => m.statement));
    this.state.update(this.time);
    this.timeline.cursor(this.time);
    this.swimlanes.cursor(this.time);
    this.draw();
  }

  packetsAt(t) {
    const last = lastAtOrBefore(this.packets, t, (p) => p.start_ms);
    const out = [];
    for (let i = last; i >= 0 && out.length < 400; i--) {
      const p = this.packets[i];
      if (p.start_ms < t - 1000) break;
      if (t <= p.end_ms + PACKET_SHOWN_MS) out.push(p);
    }
    return out;
  }

  draw() {
    this.scene.render();
    this.labels.forEach((label, i) => {
      const shown = this.showNames || this.hovered === i;
      const s = this.scene.screen(i);
      label.style.display = shown && s.visible ? 'block' : 'none';
      label.style.left = `${s.x}px`;
      label.style.top = `${s.y}px`;
    });
  }

  savePng() {
    this.draw();
    const link = element('a', { download: `${this.rec.title.replace(/[^A-Za-z0-9_-]+/g, '_')}-${Math.round(this.time)}ms.png` });
    link.href = this.scene.renderer.domElement.toDataURL('image/png');
    link.click();
  }

  // What the tests read from the page.
  probe() {
    return {
      time_ms: this.time,
      positions: this.scene.centres.map((c) => c.toArray()),
      highlighted: this.source.highlighted(),
      state: this.state.rows(),
      markers: this.timeline.markerPositions(),
    };
  }
}

function start() {
  const data = document.getElementById('recording');
  const recording = JSON.parse(data.textContent);
  // The trace event vocabulary, written into the page beside the recording.
  const vocabulary = JSON.parse(document.getElementById('vocabulary').textContent);
  const viewer = new Viewer(recording, vocabulary);
  window.dynaroleViewer = viewer;
  // `#t=MS` opens the page at that time (links to a moment, screenshots).
  const at = /[#&]t=([0-9.]+)/.exec(window.location.hash);
  if (at) viewer.seek(Number(at[1]));
  // Time from the start of navigation to a page ready to play (read by the tests).
  runProbe(viewer, performance.now());
}

start();
