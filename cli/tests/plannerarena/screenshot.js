// Screenshots of Planner Arena's "Progress" and "Overall performance" tabs, each served by
// serve_tab.py (ports 8766 and 8767), once Shiny has drawn its plot: Node.js with
// playwright-core driving Debian's chromium. Writes plannerarena-<tab>.png into argv[2].
const { chromium } = require('playwright-core');
const out = process.argv[2] || '.';
(async () => {
  const b = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  for (const [port, name] of [[8766, 'progress'], [8767, 'performance']]) {
    const p = await b.newPage({ viewport: { width: 1280, height: 1000 } });
    await p.goto(`http://127.0.0.1:${port}/`);
    await p.waitForSelector('img[src^="data:image"]', { timeout: 60000 });
    await p.screenshot({ path: `${out}/plannerarena-${name}.png`, fullPage: true });
  }
  await b.close();
})().catch((e) => { console.error(e.message); process.exit(1); });
