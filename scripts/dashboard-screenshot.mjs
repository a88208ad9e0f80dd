// Takes a PNG of a running `rockwatch dashboard` once wall WALL's banner shows LEVEL (then DELAY ms later), with the
// headless Debian chromium and playwright-core of the dashboard's browser test (`npm ci`: scripts/install-deps.sh).
// The README's screenshot (docs/dashboard.png) was taken during the demo with:
//   rockwatch demo --dashboard --dashboard-http 127.0.0.1:8080 &
//   node scripts/dashboard-screenshot.mjs --url http://127.0.0.1:8080/ --out docs/dashboard.png
// Options: --level COLLAPSED (default), --wall wall, --delay-ms 1500, --timeout-s 120, --width 1400, --height 1000.
import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const o = { level: 'COLLAPSED', wall: 'wall', 'delay-ms': '1500', 'timeout-s': '120', width: '1400', height: '1000' };
for (let i = 2; i < process.argv.length; i += 2) o[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
if (!o.url || !o.out) {
  console.error('usage: node scripts/dashboard-screenshot.mjs --url URL --out FILE.png [--level L] [--wall W]');
  process.exit(2);
}
const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const { chromium } = createRequire(path.join(root, 'package.json'))('playwright-core');
const executablePath = process.env.CHROMIUM || execFileSync('sh', ['-c', 'command -v chromium']).toString().trim();
const browser = await chromium.launch({ executablePath, headless: true, args: ['--no-sandbox', '--disable-gpu'] });
try {
  const page = await browser.newPage({ viewport: { width: Number(o.width), height: Number(o.height) } });
  await page.goto(o.url);
  const selector = `[data-testid="level"][data-wall="${o.wall}"]`;
  await page.waitForFunction(([s, l]) => document.querySelector(s) && document.querySelector(s).textContent === l,
    [selector, o.level], { timeout: Number(o['timeout-s']) * 1000, polling: 50 });
  await page.waitForTimeout(Number(o['delay-ms']));
  await page.screenshot({ path: o.out, fullPage: true });
  console.log(`screenshot of ${o.url} (wall ${o.wall} at ${o.level}): ${o.out}`);
} finally {
  await browser.close();
}
