// Debug mode's sampling tools: the BSDF sampler (POST /api/debug/bsdf: the
// material's sample_f many times at a pixel's first hit; a histogram of the
// directions' density against the pdf, or a delta BSDF's directions and
// Fresnel split) and the environment map's sampling density
// (/api/debug/envmap). debug.js runs the calls; this module lists and draws
// their results, with the helpers debug.js passes in.

// Canvas colours: the samples (bars, dots) and the pdf (line), as the 3D view draws them.
const SAMPLED = '#4fc3f7', PDF = '#ffb74d', BAD = '#ff5252', AXIS = '#9a9a9a', TEXT = '#dddddd';
const SCATTER = {reflected: '#7cff6b', refracted: '#ff9a2e'};

export function createSampling({el, f, fc, num, kv, overlay, sceneSize, COLORS}) {
  const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
  const scale = (a, k) => [a[0] * k, a[1] * k, a[2] * k];

  function canvas(id, w, h) {
    const c = el('canvas', {id, width: w, height: h, class: 'dbg-plot'});
    const g = c.getContext('2d');
    g.fillStyle = '#1e1f22';
    g.fillRect(0, 0, w, h);
    g.font = '11px ui-monospace, monospace';
    return [c, g];
  }

  // ------------------------------------------------------------ BSDF sampler

  function showBsdf(out, r) {
    const n = r.samples.length;
    const rows = [['material', `${r.material_name}: ${r.model}${r.delta ? ' (delta)' : ''}`],
                  ['at', `pixel (${r.pixel[0]}, ${r.pixel[1]}), part ${r.part}: point ${f(r.point)}, normal ${f(r.normal)}`],
                  ['wo (local, z = normal)', f(r.wo_local)],
                  ['samples', `${n} (seed ${r.seed}); no direction (pdf 0): ${r.no_direction}`]];
    if (!r.delta) {
      rows.push(['pdf over the sphere', `${f(r.pdf_integral)} (1 − the chance of no direction)`]);
      if (r.pdf_mismatches) rows.push(['pdf', `${r.pdf_mismatches} sample(s) whose pdf from sample_f ≠ pdf(wo, wi)`, 'error']);
    }
    rows.push(['verdict', r.verdict, r.agrees ? 'match' : 'mismatch']);
    if (r.error) rows.push(['error', r.error, 'error']);
    kv(out, rows).id = 'dbg-bsdf-summary';
    if (r.error) return;
    out.append(lobePlot(r));
    if (r.delta) showDirections(out, r);
    else out.append(histogramPlot(r), el('div', {class: 'note'},
      `bars: the samples' density in each 3° band of θ (count ÷ (n × the band's solid angle)); line: the pdf's mean over ` +
      `the band (its integral ÷ the solid angle). A red bar differs by more than ${f(r.z_bound)} standard deviations ` +
      `(bands expected to hold under ${f(r.min_expected)} samples are judged pooled: ${r.pooled.count} drawn, ` +
      `${f(r.pooled.expected)} expected).`));
  }

  // A delta BSDF: its directions, how often each was chosen and the
  // probability it reported for the choice (glass: Schlick's R and 1 − R).
  function showDirections(out, r) {
    const n = r.samples.length;
    const t = el('table', {class: 'dirs', id: 'dbg-bsdf-directions'});
    t.append(el('tr', {}, ...['scatter', 'wi (local)', 'chosen', 'reported probability', 'z', 'f·|cos θ|/pdf', 'geometry']
      .map((h) => el('th', {}, h))));
    for (const d of r.directions) {
      const geometry = d.scatter === 'reflected' ? `|wi − mirror of wo| ${f(d.mirror_error)}`
                                                 : `sin θo / sin θi ${f(d.sine_ratio)}`;
      t.append(el('tr', {'data-scatter': d.scatter, class: Math.abs(num(d.z)) <= r.z_bound ? '' : 'mismatch'},
        ...[d.scatter, f(d.wi_local), `${d.count} (${(100 * d.count / n).toFixed(1)}%)`, f(d.pdf), f(d.z), fc(d.weight), geometry]
          .map((v) => el('td', {}, v))));
    }
    out.append(t);
    const refl = r.directions.find((d) => d.scatter === 'reflected'), refr = r.directions.find((d) => d.scatter === 'refracted');
    if (refl && refr) {
      out.append(el('div', {class: 'note', id: 'dbg-bsdf-fresnel'},
        `Fresnel split: ${(100 * refl.count / n).toFixed(1)}% reflected, ${(100 * refr.count / n).toFixed(1)}% refracted; ` +
        `reported R = ${f(refl.pdf)}, 1 − R = ${f(refr.pdf)}. Snell: sin θo / sin θi is the ratio of the indices.`));
    }
  }

  // The directions seen edge-on: the plane of the normal (up) and wo (to
  // the left), each sample a dot at (wi along wo's side, wi.z); the upper
  // half is the hemisphere of wo, the lower one below the surface.
  function lobePlot(r) {
    const W = 560, H = 250, R = 100, cx = W / 2, cy = H / 2;
    const [c, g] = canvas('dbg-bsdf-lobe', W, H);
    const wo = r.wo_local, t = Math.hypot(wo[0], wo[1]);
    const u = t > 1e-6 ? [wo[0] / t, wo[1] / t] : [1, 0];
    const at = (w) => [cx - R * (w[0] * u[0] + w[1] * u[1]), cy - R * w[2]];
    g.strokeStyle = AXIS;
    g.beginPath();
    g.arc(cx, cy, R, 0, 2 * Math.PI);
    g.moveTo(cx - R - 8, cy);
    g.lineTo(cx + R + 8, cy);
    g.stroke();
    g.setLineDash([4, 4]);
    g.beginPath();
    g.moveTo(cx, cy);
    g.lineTo(cx, cy - R - 8);
    g.stroke();
    g.setLineDash([]);
    const arrow = (w, color, width, label) => {
      const [x, y] = at(w);
      g.strokeStyle = color;
      g.lineWidth = width;
      g.beginPath();
      g.moveTo(cx, cy);
      g.lineTo(x, y);
      g.stroke();
      g.lineWidth = 1;
      if (label) {
        g.fillStyle = color;
        const w = g.measureText(label).width;
        const lx = Math.min(W - w - 2, Math.max(2, x + (x < cx ? -4 - w : 4)));
        g.fillText(label, lx, Math.min(H - 4, Math.max(11, y + (y < cy ? -3 : 11))));
      }
    };
    if (r.delta) {
      for (const d of r.directions) arrow(d.wi_local, SCATTER[d.scatter] || SAMPLED, 3,
                                          `${d.scatter} ${(100 * d.count / r.samples.length).toFixed(1)}%`);
    } else {
      g.fillStyle = SAMPLED;
      g.globalAlpha = 0.5;
      for (const s of r.samples) {
        if (!(num(s.pdf) > 0)) continue;
        const [x, y] = at(s.wi_local);
        g.fillRect(x - 1, y - 1, 2, 2);
      }
      g.globalAlpha = 1;
    }
    arrow(wo, TEXT, 2, 'wo');
    g.fillStyle = AXIS;
    g.fillText('normal', cx + 4, 12);
    g.fillText('surface', cx + R + 12, cy + 4);
    g.fillText('edge-on: the plane of the normal and wo', 6, 14);
    return c;
  }

  // Density per steradian against θ: bars for the samples, a line for the pdf.
  function histogramPlot(r) {
    const W = 560, H = 230, left = 52, right = 10, top = 22, bottom = 34;
    const [c, g] = canvas('dbg-bsdf-histogram', W, H);
    const bins = r.histogram, span = bins.length ? bins.at(-1).theta[1] : 90;
    const ymax = 1.1 * Math.max(1e-9, ...bins.map((b) => Math.max(b.sampled_density, b.pdf_density)));
    const X = (deg) => left + (W - left - right) * deg / span, Y = (d) => H - bottom - (H - top - bottom) * d / ymax;
    for (const b of bins) {
      const bad = b.judged && !(Math.abs(num(b.z)) <= r.z_bound);
      g.fillStyle = bad ? BAD : SAMPLED;
      g.globalAlpha = 0.75;
      g.fillRect(X(b.theta[0]) + 0.5, Y(b.sampled_density), X(b.theta[1]) - X(b.theta[0]) - 1, H - bottom - Y(b.sampled_density));
    }
    g.globalAlpha = 1;
    g.strokeStyle = PDF;
    g.lineWidth = 2;
    g.beginPath();
    bins.forEach((b, i) => {
      g[i ? 'lineTo' : 'moveTo'](X(b.theta[0]), Y(b.pdf_density));
      g.lineTo(X(b.theta[1]), Y(b.pdf_density));
    });
    g.stroke();
    g.lineWidth = 1;
    // Axes, ticks every 15 degrees, the density's scale.
    g.strokeStyle = AXIS;
    g.fillStyle = TEXT;
    g.beginPath();
    g.moveTo(left, top);
    g.lineTo(left, H - bottom);
    g.lineTo(W - right, H - bottom);
    g.stroke();
    for (let deg = 0; deg <= span; deg += span > 90 ? 30 : 15) {
      g.fillText(`${deg}°`, X(deg) - 8, H - bottom + 13);
    }
    for (const k of [0, 0.5, 1]) {
      const d = k * ymax / 1.1;
      g.fillText(f(Number(d.toPrecision(2))), 4, Y(d) + 4);
    }
    g.fillText('θ, the angle of wi to the normal', W / 2 - 90, H - 6);
    g.fillText('density (1/sr)', 4, 12);
    g.fillStyle = SAMPLED;
    g.fillRect(W - 230, 6, 12, 10);
    g.fillStyle = TEXT;
    g.fillText('samples', W - 214, 15);
    g.strokeStyle = PDF;
    g.lineWidth = 2;
    g.beginPath();
    g.moveTo(W - 150, 11);
    g.lineTo(W - 136, 11);
    g.stroke();
    g.fillText('pdf reported', W - 130, 15);
    return c;
  }

  // In 3D: a dot per sample at the point + wi (a lobe around the hit), the
  // delta directions as lines, wo in white and the normal.
  function drawBsdf(r) {
    if (r.error || !r.samples.length) return;
    const size = sceneSize(), len = 0.15 * size;
    if (r.delta) {
      for (const d of r.directions) {
        overlay.segments([[r.point, add(r.point, scale(d.wi, 1.5 * len))]], d.scatter === 'reflected' ? COLORS.hit : COLORS.shape);
      }
    } else {
      overlay.points(r.samples.filter((s) => num(s.pdf) > 0).map((s) => add(r.point, scale(s.wi, len))), COLORS.bounce, 3);
    }
    overlay.segments([[r.point, add(r.point, scale(r.wo, 1.5 * len))]], COLORS.ray);
    overlay.points([r.point], COLORS.point, 8);
    overlay.arrow(r.point, r.normal, 0.6 * len, COLORS.normal);
  }

  // ---------------------------------------------------- environment density

  function showEnvmap(out, r) {
    const rows = [['map', `${r.width} × ${r.height} texels`], ['sampler', `${r.sampler}, part ${r.part}`],
                  ['most likely texel', `${f(r.max_ratio)} × the average texel (1/(w h))`],
                  ['the likeliest 1% of texels', `${(100 * r.top_share).toFixed(1)}% of the directions`],
                  ['sum of the probabilities', f(r.total)]];
    if (r.note) rows.push(['note', r.note, 'error']);
    if (r.error) rows.push(['error', r.error, 'error']);
    kv(out, rows).id = 'dbg-envmap-summary';
    if (!r.png) return;
    const img = el('img', {id: 'dbg-envmap-img', src: r.png, alt: 'each texel\'s probability of being sampled'});
    out.append(img, greyScale(), el('div', {class: 'note'},
      'Each texel\'s probability of being drawn by the render\'s sampler of the map (pathtracer --env-probability), ' +
      'on a log scale: mid-grey is the average texel, white 1000 times more likely, black 1000 times less (or never). ' +
      'The map\'s top row is straight up.'));
  }

  function greyScale() {
    const W = 560, H = 34;
    const [c, g] = canvas('dbg-envmap-scale', W, H);
    const grad = g.createLinearGradient(40, 0, W - 40, 0);
    grad.addColorStop(0, '#000');
    grad.addColorStop(1, '#fff');
    g.fillStyle = grad;
    g.fillRect(40, 4, W - 80, 12);
    g.fillStyle = TEXT;
    [['≤ 1/1000', 0], ['1/10', 1 / 3], ['average', 0.5], ['×10', 2 / 3], ['≥ ×1000', 1]].forEach(([label, k]) => {
      const x = 40 + k * (W - 80);
      g.fillText(label, Math.min(W - g.measureText(label).width - 2, Math.max(2, x - g.measureText(label).width / 2)), 30);
    });
    return c;
  }

  return {showBsdf, drawBsdf, showEnvmap};
}
