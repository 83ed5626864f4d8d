// The value after a command-line flag: `const option = optionReader(process.argv.slice(2))`, then
// `option('--level', '5')` gives the word after --level, or '5' when the flag or its value is missing.
export const optionReader = (args) => (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 && args[i + 1] ? args[i + 1] : fallback;
};
