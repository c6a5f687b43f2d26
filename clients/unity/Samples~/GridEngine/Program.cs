using System;
using System.Threading;
using Toyroom.Engine;
using Toyroom.Transport;

namespace Toyroom.Samples.GridEngine
{
    /// <summary>
    /// <c>mono GridEngine.exe --gateway ws://127.0.0.1:7448 --scenarios DIR [--scenario NAME] [--robot act|observe]</c>:
    /// the paper's scenarios on a grid, as an engine of the world the gateway carries, until
    /// the gateway goes away or the process is stopped. Scenarios are <c>toyroom export-scenario</c>
    /// files, <c>DIR/NAME.json</c>.
    /// </summary>
    public static class Program
    {
        public static int Main(string[] args)
        {
            string url = "ws://127.0.0.1:7448", folder = ".", scenario = "paper-robot", token = null;
            bool? robot = null;
            for (var i = 0; i < args.Length; i++)
            {
                var value = i + 1 < args.Length ? args[i + 1] : null;
                switch (args[i])
                {
                    case "--gateway": url = value; i++; break;
                    case "--scenarios": folder = value; i++; break;
                    case "--scenario": scenario = value; i++; break;
                    case "--token": token = value; i++; break;
                    case "--robot": robot = value == "act"; i++; break;
                    case "--log-level": i++; break; // accepted for symmetry with sim2d
                    case "--lockstep": break; // always lock-step
                    default:
                        Console.Error.WriteLine("grid engine: unknown option " + args[i]);
                        return 2;
                }
                if (value == null && args[i] != "--lockstep")
                {
                    Console.Error.WriteLine("grid engine: " + args[i] + " needs a value");
                    return 2;
                }
            }
            GridGame game;
            try
            {
                game = new GridGame(folder, scenario, robot);
            }
            catch (UnknownScenario error)
            {
                Console.Error.WriteLine("grid engine: " + error.Message);
                return 2;
            }
            using (var gateway = new GatewayClient(url))
            {
                var lost = new ManualResetEvent(false);
                gateway.Closed += reason => { Console.Error.WriteLine("grid engine: " + reason); lost.Set(); };
                try
                {
                    gateway.Connect("engine", "csharp", token, TimeSpan.FromSeconds(10));
                }
                catch (Exception error)
                {
                    Console.Error.WriteLine("grid engine: " + error.Message);
                    return 1;
                }
                if (!gateway.NagleOff)
                    Console.Error.WriteLine("grid engine: could not turn Nagle's algorithm off: ticks may take 40 ms");
                var host = new EngineHost(game, gateway);
                host.Start();
                Console.WriteLine("grid engine (C#): scenario '" + scenario + "' on world '" + gateway.Welcome.World + "'");
                while (!lost.WaitOne(0))
                {
                    if (host.Wait(TimeSpan.FromMilliseconds(200))) host.Pump();
                }
                return 1; // without its gateway the engine has no peers left
            }
        }
    }
}
